//! A disk light, one-sided, emitting along its normal with uniform
//! radiance; sampled through its shape
//! ([`Shape::sample`](crate::geometry::Shape::sample)), here its intensity
//! under the thesis model.

use std::f32::consts::PI;

use crate::math::{Rgb, Vec3};

/// Intensity toward direction `w` (unit, from the light) of the disk facing
/// `n` collapsed to a point: `L · π r² · cos θ`.
#[inline]
pub(super) fn intensity(power: Rgb, n: Vec3, radius: f32, w: Vec3) -> Rgb {
    power * (PI * radius * radius * n.dot(w).max(0.0))
}
