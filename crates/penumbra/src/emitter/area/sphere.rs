//! A sphere light, emitting outward with uniform radiance; sampled through
//! its shape ([`Shape::sample`](crate::geometry::Shape::sample)), here its
//! intensity under the thesis model.

use std::f32::consts::PI;

use crate::math::Rgb;

/// Intensity of the sphere collapsed to a point: `L · π r²` in every direction.
#[inline]
pub(super) fn intensity(power: Rgb, radius: f32) -> Rgb {
    power * (PI * radius * radius)
}
