//! A disk light, one-sided, emitting along `frame.n` with uniform radiance;
//! sampled uniformly over its area.

use std::f32::consts::PI;

use crate::emitter::sample::{area_sample, LightSample};
use crate::math::{Frame, Rgb, Vec3};
use crate::sampling::points::unit_disk;
use crate::sampling::Distribution;

pub(super) fn area(radius: f32) -> f32 {
    PI * radius * radius
}

/// Intensity toward direction `w` (unit, from the light) of the disk
/// collapsed to a point: `L · π r² · cos θ`.
#[inline]
pub(super) fn intensity(power: Rgb, n: Vec3, radius: f32, w: Vec3) -> Rgb {
    power * (PI * radius * radius * n.dot(w).max(0.0))
}

/// A uniform point of the disk for the distribution point `point`.
#[inline]
pub(super) fn sample(
    power: Rgb,
    center: Vec3,
    frame: &Frame,
    radius: f32,
    p: Vec3,
    point: Vec3,
    d: Distribution,
) -> Option<LightSample> {
    let u = unit_disk(point, d) * radius;
    let target = center + u.x * frame.u + u.y * frame.v;
    area_sample(power, p, target, frame.n, area(radius), false)
}
