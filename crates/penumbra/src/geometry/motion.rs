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
    /// World-from-object matrix at frame time `time` (clamped to [0, 1]).
    pub fn matrix_at(&self, time: f32) -> Mat4 {
        self.start.lerp(&self.end, time.clamp(0.0, 1.0)).matrix()
    }

    /// Transforms a world ray into object space at the ray's time.
    /// The direction is not renormalised, so hit distances `t` are shared.
    pub fn to_object(&self, ray: &Ray) -> (Ray, Mat4) {
        let m = self.matrix_at(ray.time);
        let inv = m.inverse();
        let r = Ray::new(
            inv.transform_point3(ray.origin),
            inv.transform_vector3(ray.dir),
            ray.time,
        );
        (r, m)
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
