//! Rigid motion over the shutter: an object's placement at frame time 0 and 1,
//! interpolated per ray time.
//!
//! Placements are decomposed into scale, rotation and translation and
//! interpolated component-wise (lerp, slerp, lerp), as pbrt's animated
//! transforms do: interpolating matrices directly would shear and shrink a
//! rotating object half-way through.

use crate::math::{Aabb, Mat4, Quat, Ray, Vec3};

/// A transform decomposed as `T · R · S` (scale first, as in scene files).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    pub scale: Vec3,
    pub rotation: Quat,
    pub translation: Vec3,
}

impl Similarity {
    pub const IDENTITY: Similarity = Similarity {
        scale: Vec3::ONE,
        rotation: Quat::IDENTITY,
        translation: Vec3::ZERO,
    };

    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }

    /// Object-space point of a world point (the inverse, `S⁻¹ R⁻¹ (p − t)`,
    /// without inverting a matrix).
    #[inline]
    pub fn point_to_local(&self, p: Vec3) -> Vec3 {
        self.rotation.conjugate() * (p - self.translation) / self.scale
    }

    /// Object-space direction of a world direction (lengths change with scale).
    #[inline]
    pub fn vector_to_local(&self, v: Vec3) -> Vec3 {
        self.rotation.conjugate() * v / self.scale
    }

    #[inline]
    pub fn point_to_world(&self, p: Vec3) -> Vec3 {
        self.rotation * (p * self.scale) + self.translation
    }

    /// World vector of an object-space vector (a tangent: lengths change
    /// with scale).
    #[inline]
    pub fn vector_to_world(&self, v: Vec3) -> Vec3 {
        self.rotation * (v * self.scale)
    }

    /// World normal of an object-space normal: the inverse transpose of
    /// `R S` is `R S⁻¹`.
    #[inline]
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        (self.rotation * (n / self.scale)).normalize_or_zero()
    }

    fn lerp(&self, other: &Similarity, u: f32) -> Similarity {
        Similarity {
            scale: self.scale.lerp(other.scale, u),
            rotation: self.rotation.slerp(other.rotation, u),
            translation: self.translation.lerp(other.translation, u),
        }
    }
}

/// An object's placement over the frame: fixed, or moving between two placements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub start: Similarity,
    pub end: Similarity,
}

/// Number of time steps at which a moving object's bounds are sampled; the
/// union is then padded, because slerp sweeps arcs between the samples.
const BOUND_STEPS: usize = 64;

impl Motion {
    /// The placement at frame time `time` (clamped to [0, 1]).
    #[inline]
    pub fn at(&self, time: f32) -> Similarity {
        self.start.lerp(&self.end, time.clamp(0.0, 1.0))
    }

    /// World-from-object matrix at frame time `time`.
    pub fn matrix_at(&self, time: f32) -> Mat4 {
        self.at(time).matrix()
    }

    /// Transforms a world ray into object space at the ray's time, with the
    /// placement used. The direction is not renormalised, so hit distances
    /// `t` are the same in both spaces.
    #[inline]
    pub fn to_object(&self, ray: &Ray) -> (Ray, Similarity) {
        let s = self.at(ray.time);
        let r = Ray::new(
            s.point_to_local(ray.origin),
            s.vector_to_local(ray.dir),
            ray.time,
        );
        (r, s)
    }

    /// Conservative world bounds of object bounds `b` over the whole frame.
    pub fn bounds(&self, b: Aabb) -> Aabb {
        let mut out = Aabb::EMPTY;
        for i in 0..=BOUND_STEPS {
            let m = self.matrix_at(i as f32 / BOUND_STEPS as f32);
            out = out.union(transform_box(&m, b));
        }
        let pad = out.extent().max_element() * (std::f32::consts::PI / BOUND_STEPS as f32).powi(2);
        Aabb::new(out.min - Vec3::splat(pad), out.max + Vec3::splat(pad))
    }
}

/// Bounds of a transformed box (its eight transformed corners).
pub fn transform_box(m: &Mat4, b: Aabb) -> Aabb {
    let mut out = Aabb::EMPTY;
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        );
        out = out.grow(m.transform_point3(c));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halfway_translation_and_rotation() {
        let start = Similarity::IDENTITY;
        let end = Similarity {
            scale: Vec3::ONE,
            rotation: Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
            translation: Vec3::new(2.0, 0.0, 0.0),
        };
        let m = Motion { start, end };
        let p = m.matrix_at(0.5).transform_point3(Vec3::X);
        let a = std::f32::consts::FRAC_PI_4;
        assert!((p - Vec3::new(1.0 + a.cos(), 0.0, -a.sin())).length() < 1e-5);
    }

    #[test]
    fn local_and_world_round_trip() {
        let s = Similarity {
            scale: Vec3::new(2.0, 0.5, 3.0),
            rotation: Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7),
            translation: Vec3::new(-1.0, 4.0, 2.0),
        };
        let p = Vec3::new(0.3, -0.2, 0.9);
        assert!((s.point_to_world(s.point_to_local(p)) - p).length() < 1e-5);
        assert!((s.matrix().transform_point3(s.point_to_local(p)) - p).length() < 1e-5);
        let n = Vec3::new(0.0, 1.0, 0.0);
        let want = s
            .matrix()
            .inverse()
            .transpose()
            .transform_vector3(n)
            .normalize();
        assert!((s.normal_to_world(n) - want).length() < 1e-5);
    }

    #[test]
    fn bounds_cover_every_time() {
        let m = Motion {
            start: Similarity::IDENTITY,
            end: Similarity {
                scale: Vec3::splat(2.0),
                rotation: Quat::from_rotation_z(2.0),
                translation: Vec3::new(0.0, 3.0, 0.0),
            },
        };
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let wb = m.bounds(b);
        for i in 0..=1000 {
            let mt = m.matrix_at(i as f32 / 1000.0);
            let tb = transform_box(&mt, b);
            assert!(tb.min.cmpge(wb.min).all() && tb.max.cmple(wb.max).all());
        }
    }
}
