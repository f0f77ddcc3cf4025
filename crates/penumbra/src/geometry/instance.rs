//! Instancing (Mitsuba 3's `shapegroup` and `instance`): a group of shapes
//! built once, placed many times, each placement a transform of the same
//! geometry.
//!
//! The scene's world holds two levels (see [`World`]): its top-level tree
//! has one entry per shape of each instance, holding the instance's
//! [`Placement`] and a reference to the shape's geometry in the group's
//! own space: for a mesh, one triangle tree shared by every instance of
//! the group; for an analytic shape, its parameters. A ray reaching such
//! an entry is carried into the group's space by the inverse transform
//! (its direction not renormalised, so distances `t` are the same in both
//! spaces), and the hit's point, normals (by the inverse transpose) and
//! tangents are carried back to world space; its material is that of the
//! group's shape.
//!
//! `shapegroup` parameters: none but its shapes. `instance` parameters:
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `group` | string | **required** | the name of the group (a `[groups.NAME]` table) |
//! | `transform` | transform | identity | the placement, any invertible affine map |
//!
//! A group may hold neither an instance, as in Mitsuba, nor a moving
//! shape. Unlike Mitsuba's, it may hold emitters: each instance of an
//! emitting shape is an emitter of its own (a
//! [`Surface`](super::Surface) placed by the instance).
//!
//! [`World`]: crate::accel::World

use crate::math::{Aabb, Mat4, Ray, Vec3};

/// An instance's transform, its inverse and the inverse transpose that
/// carries normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub to_world: Mat4,
    pub to_object: Mat4,
    /// The inverse transpose of `to_world`'s linear part.
    normals: Mat4,
}

impl Placement {
    /// The placement of the affine map `m`; `None` when `m` is singular,
    /// not finite or projective.
    pub fn new(m: Mat4) -> Option<Placement> {
        let affine = m.row(3) == glam::Vec4::W;
        let det = m.determinant();
        if !affine || !m.is_finite() || !det.is_normal() {
            return None;
        }
        let to_object = m.inverse();
        if !to_object.is_finite() {
            return None;
        }
        Some(Placement {
            to_world: m,
            to_object,
            normals: to_object.transpose(),
        })
    }

    /// The ray in the group's space, its direction not renormalised.
    #[inline]
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(ray.origin),
            self.to_object.transform_vector3(ray.dir),
            ray.time,
        )
    }

    #[inline]
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.to_world.transform_point3(p)
    }

    /// A tangent vector in world space.
    #[inline]
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.to_world.transform_vector3(v)
    }

    /// A unit normal in world space (by the inverse transpose).
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        self.normals.transform_vector3(n).normalize_or_zero()
    }

    /// World bounds of the group-space box `b`.
    pub fn bounds(&self, b: Aabb) -> Aabb {
        super::motion::transform_box(&self.to_world, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sheared, scaled, rotated placement: normals stay perpendicular to
    /// transformed tangents, rays keep their distances, and singular or
    /// projective maps are refused.
    #[test]
    fn normals_stay_normal_and_distances_stay() {
        let m = Mat4::from_cols_array(&[
            2.0, 0.3, 0.0, 0.0, 0.5, 1.0, 0.2, 0.0, 0.0, -0.4, 0.7, 0.0, 1.0, 2.0, 3.0, 1.0,
        ]);
        let pl = Placement::new(m).unwrap();
        let n = Vec3::new(0.2, 0.5, 0.8).normalize();
        let t = n.any_orthonormal_vector();
        let (nw, tw) = (pl.normal_to_world(n), pl.vector_to_world(t));
        assert!(nw.dot(tw).abs() < 1e-5 * tw.length(), "{}", nw.dot(tw));
        assert!((nw.length() - 1.0).abs() < 1e-6);
        let ray = Ray::new(Vec3::new(4.0, -1.0, 2.0), Vec3::new(-0.3, 0.6, 0.2), 0.0);
        let local = pl.ray_to_object(&ray);
        let back = pl.point_to_world(local.at(1.7));
        assert!((back - ray.at(1.7)).length() < 1e-5);
        assert!(Placement::new(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
        assert!(Placement::new(Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.5, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]))
        .is_none());
        assert!(Placement::new(Mat4::from_translation(Vec3::splat(f32::NAN))).is_none());
    }
}
