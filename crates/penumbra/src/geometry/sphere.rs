//! The sphere: every point at distance `radius` from `center`.
//!
//! Its surface coordinates are Mitsuba's (poles on the z axis):
//! `u = φ / 2π`, `v = θ / π`. Seen from outside, a light of this shape is
//! sampled uniformly in the solid angle it subtends (every point drawn is
//! on the visible cap); from inside, uniformly in area.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `center` | point | `[0, 0, 0]` | centre |
//! | `radius` | number > 0 | `1` | radius |

use std::f32::consts::{PI, TAU};

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::model::{angle, area_pdf, Density, MeshTable, ShapeHit, ShapeModel, ShapeSample};
use crate::math::{Aabb, Frame, Mat4, Ray, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::warp::{square_to_uniform_cone, square_to_uniform_sphere};
use crate::sampling::Distribution;

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn new(center: Vec3, radius: f32) -> Sphere {
        Sphere { center, radius }
    }
}

impl ShapeModel for Sphere {
    const NAME: &'static str = "sphere";

    fn bounds(&self, _meshes: &[Mesh]) -> Aabb {
        let r = Vec3::splat(self.radius);
        Aabb::new(self.center - r, self.center + r)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
        intersect_sphere(ray, self.center, self.radius, tmin, tmax).map(ShapeHit::at)
    }

    #[inline]
    fn geometry(&self, _meshes: &[Mesh], _hit: &ShapeHit, p: Vec3) -> LocalGeometry {
        sphere_geometry(p - self.center)
    }

    fn area(&self, _meshes: &[Mesh]) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    #[inline]
    fn is_closed(&self) -> bool {
        true
    }

    fn center(&self, _meshes: &[Mesh]) -> Vec3 {
        self.center
    }

    fn size(&self) -> Option<f32> {
        Some(self.radius)
    }

    fn projected_area(&self, _w: Vec3) -> Option<f32> {
        Some(PI * self.radius * self.radius)
    }

    fn transformed(&self, m: &Mat4, scale: f32) -> Option<Sphere> {
        Some(Sphere::new(
            m.transform_point3(self.center),
            self.radius * scale,
        ))
    }

    #[inline]
    fn uniform_in_area(&self) -> bool {
        false
    }

    #[inline(always)]
    fn sample(
        &self,
        _meshes: &[Mesh],
        _mesh: MeshTable,
        from: Vec3,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        Some(sample_sphere(
            self.center,
            self.radius,
            from,
            unit_square(point, d),
        ))
    }

    #[inline]
    fn density(&self, area: f32, from: Vec3, target: Vec3, n: Vec3) -> f32 {
        let to = target - from;
        let r2 = to.length_squared();
        let cos_l = n.dot(-to) / r2.sqrt();
        let radius = self.radius;
        let d2 = (self.center - from).length_squared();
        if d2 <= radius * radius {
            return area_pdf(cos_l.abs(), r2, area);
        }
        1.0 / (2.0 * PI * (1.0 - cos_max(radius, d2)))
    }
}

/// The cosine of the half-angle of the cone a sphere of radius `radius`
/// subtends from a point at squared distance `d2` from its centre
/// (outside it).
fn cos_max(radius: f32, d2: f32) -> f32 {
    (1.0 - radius * radius / d2).max(0.0).sqrt()
}

/// A point of the sphere seen from `from`: from outside, uniform in the
/// cone it subtends (on the near side); from inside, uniform in area.
#[inline(never)]
fn sample_sphere(c: Vec3, r: f32, from: Vec3, u: Vec2) -> ShapeSample {
    let to_c = c - from;
    let d2 = to_c.length_squared();
    if d2 <= r * r {
        let n = square_to_uniform_sphere(u);
        return ShapeSample {
            p: c + r * n,
            n,
            density: Density::Area {
                area: 4.0 * PI * r * r,
                two_sided: true,
            },
            hit: ShapeHit::default(),
            local: c + r * n,
        };
    }
    let d = d2.sqrt();
    let cos_max = cos_max(r, d2);
    let frame = Frame::from_normal(to_c / d);
    let w = frame.to_world(square_to_uniform_cone(u, cos_max));
    // Distance to the near side of the sphere along w (clamped to the
    // tangent point when rounding puts w just outside the cone).
    let b = w.dot(to_c);
    let disc = (r * r - (d2 - b * b)).max(0.0);
    let p = from + (b - disc.sqrt()) * w;
    ShapeSample {
        p,
        n: (p - c) / r,
        density: Density::Cone(2.0 * PI * (1.0 - cos_max)),
        hit: ShapeHit::default(),
        local: p,
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

/// Ray–sphere intersection, nearest root in (tmin, tmax).
///
/// Uses the numerically stable form: the discriminant is computed from the
/// distance of the centre to the ray line (`|oc - (oc·d)d|²`) rather than
/// `b² - 4ac`, which cancels catastrophically for small spheres far away.
#[inline]
pub fn intersect_sphere(ray: &Ray, center: Vec3, radius: f32, tmin: f32, tmax: f32) -> Option<f32> {
    let len2 = ray.dir.length_squared();
    let d = ray.dir / len2.sqrt();
    let oc = ray.origin - center;
    let b = oc.dot(d);
    let perp = oc - b * d;
    let disc = radius * radius - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = oc.length_squared() - radius * radius;
    let q = -b - disc.sqrt().copysign(b);
    let scale = len2.sqrt();
    let (mut t0, mut t1) = (q, if q != 0.0 { c / q } else { -q });
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let (t0, t1) = (t0 / scale, t1 / scale);
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_front_and_back() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0);
        assert!((intersect_sphere(&r, Vec3::ZERO, 1.0, 0.0, 100.0).unwrap() - 4.0).abs() < 1e-5);
        let inside = Ray::new(Vec3::ZERO, Vec3::Z * 2.0, 0.0);
        assert!(
            (intersect_sphere(&inside, Vec3::ZERO, 1.0, 0.0, 100.0).unwrap() - 0.5).abs() < 1e-5
        );
        assert!(intersect_sphere(&r, Vec3::new(0.0, 2.0, 0.0), 1.0, 0.0, 100.0).is_none());
        assert!(intersect_sphere(&r, Vec3::ZERO, 1.0, 0.0, 3.0).is_none());
    }

    #[test]
    fn small_far_sphere_is_accurate() {
        let r = Ray::new(Vec3::new(0.0, 0.0, -1.0e4), Vec3::Z, 0.0);
        let t = intersect_sphere(&r, Vec3::ZERO, 0.01, 0.0, f32::INFINITY).unwrap();
        assert!((t - (1.0e4 - 0.01)).abs() < 2e-3, "t = {t}");
    }

    /// Carried by a similarity, a sphere keeps its shape: its centre moved,
    /// its radius scaled; it shows `π r²` toward every direction.
    #[test]
    fn similar_spheres_and_their_silhouette() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(1.0, -2.0, 3.0),
        );
        let s = Sphere::new(Vec3::X, 0.5).transformed(&m, 2.0).unwrap();
        assert!((s.center - m.transform_point3(Vec3::X)).length() < 1e-6);
        assert_eq!(s.radius, 1.0);
        for w in [Vec3::X, -Vec3::Y, Vec3::new(0.6, 0.0, 0.8)] {
            assert_eq!(s.projected_area(w), Some(PI));
        }
        assert_eq!(s.size(), Some(1.0));
        assert!(s.is_closed() && !s.is_flat() && !s.uniform_in_area());
    }
}
