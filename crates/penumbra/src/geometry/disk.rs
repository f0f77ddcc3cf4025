//! The disk: a circle of radius `radius` around `center`, facing
//! `frame.n`.
//!
//! Its surface coordinates are Mitsuba's polar ones: `u = r / radius`,
//! `v = φ / 2π` (φ from the frame's `u` axis).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `center` | point | `[0, 0, 0]` | centre |
//! | `normal` | vector | `[0, 0, 1]` | the side it faces |
//! | `radius` | number > 0 | `1` | radius |

use std::f32::consts::{PI, TAU};

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::model::{
    angle, placed_frame, plane_area_scale, MeshTable, ShapeHit, ShapeModel, ShapeSample,
};
use crate::math::{Aabb, Frame, Mat4, Ray, Vec2, Vec3};
use crate::sampling::points::unit_disk;
use crate::sampling::Distribution;

/// A disk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    pub center: Vec3,
    /// `n` the side it faces; `u` and `v` the axes of its plane.
    pub frame: Frame,
    pub radius: f32,
}

impl Disk {
    pub fn new(center: Vec3, frame: Frame, radius: f32) -> Disk {
        Disk {
            center,
            frame,
            radius,
        }
    }
}

impl ShapeModel for Disk {
    const NAME: &'static str = "disk";

    fn bounds(&self, _meshes: &[Mesh]) -> Aabb {
        let e = Vec3::ONE - self.frame.n * self.frame.n;
        let r = self.radius * Vec3::from_array(e.max(Vec3::ZERO).to_array().map(f32::sqrt));
        Aabb::new(self.center - r, self.center + r)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
        intersect_disk(ray, self.center, self.frame.n, self.radius, tmin, tmax).map(ShapeHit::at)
    }

    #[inline]
    fn geometry(&self, _meshes: &[Mesh], _hit: &ShapeHit, p: Vec3) -> LocalGeometry {
        disk_geometry(p - self.center, &self.frame, self.radius)
    }

    fn area(&self, _meshes: &[Mesh]) -> f32 {
        PI * self.radius * self.radius
    }

    #[inline]
    fn is_flat(&self) -> bool {
        true
    }

    #[inline]
    fn plane(&self) -> Option<(Vec3, Vec3)> {
        Some((self.frame.n, self.center))
    }

    fn center(&self, _meshes: &[Mesh]) -> Vec3 {
        self.center
    }

    fn size(&self) -> Option<f32> {
        Some(self.radius)
    }

    fn projected_area(&self, w: Vec3) -> Option<f32> {
        Some(PI * self.radius * self.radius * self.frame.n.dot(w).max(0.0))
    }

    fn normal_cone(
        &self,
        _meshes: &[Mesh],
        _triangles: Option<&crate::sampling::Discrete>,
        flip: bool,
    ) -> (Vec3, f32) {
        (if flip { -self.frame.n } else { self.frame.n }, 1.0)
    }

    fn area_scale(&self, m: &Mat4) -> f32 {
        plane_area_scale(self.frame.u, self.frame.v, m)
    }

    fn transformed(&self, m: &Mat4, scale: f32) -> Option<Disk> {
        Some(Disk::new(
            m.transform_point3(self.center),
            placed_frame(m, &self.frame),
            self.radius * scale,
        ))
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
        let (frame, radius) = (&self.frame, self.radius);
        let u = unit_disk(point, d) * radius;
        let p = self.center + u.x * frame.u + u.y * frame.v;
        Some(ShapeSample::on_area(p, frame.n, PI * radius * radius))
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

/// Ray–disk intersection: the plane hit in (tmin, tmax), then a distance
/// test to the centre.
#[inline]
pub fn intersect_disk(ray: &Ray, c: Vec3, n: Vec3, r: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let denom = n.dot(ray.dir);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = n.dot(c - ray.origin) / denom;
    (t > tmin && t < tmax && (ray.at(t) - c).length_squared() <= r * r).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_the_rim_only() {
        let (c, n) = (Vec3::new(0.0, 2.0, 0.0), Vec3::Y);
        let down = |x: f32| Ray::new(Vec3::new(x, 5.0, 0.0), -Vec3::Y, 0.0);
        assert_eq!(intersect_disk(&down(0.5), c, n, 1.0, 0.0, 10.0), Some(3.0));
        assert_eq!(intersect_disk(&down(1.5), c, n, 1.0, 0.0, 10.0), None);
        // Outside the range, and parallel to the plane.
        assert_eq!(intersect_disk(&down(0.5), c, n, 1.0, 0.0, 2.5), None);
        let along = Ray::new(Vec3::new(-3.0, 2.0, 0.0), Vec3::X, 0.0);
        assert_eq!(intersect_disk(&along, c, n, 1.0, 0.0, 10.0), None);
    }

    /// A disk shows `π r² cos θ` toward a direction at θ to its normal, and
    /// nothing from behind; carried by a similarity, its frame stays
    /// orthonormal and its plane is the carried one.
    #[test]
    fn silhouette_and_similar_disks() {
        let d = Disk::new(Vec3::ZERO, Frame::from_normal(Vec3::Y), 2.0);
        let w = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
        let a = d.projected_area(w).unwrap();
        assert!((a - 2.0 * PI).abs() < 1e-5, "{a}");
        assert_eq!(d.projected_area(-Vec3::Y), Some(0.0));
        let m = Mat4::from_scale_rotation_translation(
            Vec3::splat(0.5),
            glam::Quat::from_rotation_x(0.4),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let t = d.transformed(&m, 0.5).unwrap();
        let f = t.frame;
        assert!((f.n - m.transform_vector3(Vec3::Y).normalize()).length() < 1e-6);
        assert!(f.u.dot(f.n).abs() < 1e-6 && (f.u.cross(f.v) - f.n).length() < 1e-5);
        assert_eq!((t.radius, t.plane().unwrap().1), (1.0, Vec3::Y));
    }
}
