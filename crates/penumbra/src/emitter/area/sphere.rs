//! A sphere light, emitting outward with uniform radiance. From outside it
//! is sampled uniformly over the cone it subtends (pdf 1/(2π(1−cos θmax))),
//! so that every sample hits the visible cap; from inside, over its area.

use std::f32::consts::PI;

use crate::emitter::sample::{area_pdf, area_sample, LightSample};
use crate::math::{Frame, Rgb, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::warp::{square_to_uniform_cone, square_to_uniform_sphere};
use crate::sampling::Distribution;

/// Intensity of the sphere collapsed to a point: `L · π r²` in every direction.
#[inline]
pub(super) fn intensity(power: Rgb, radius: f32) -> Rgb {
    power * (PI * radius * radius)
}

/// The cosine of the half-angle of the cone the sphere subtends from a point
/// at squared distance `d2` from its centre (outside it).
fn cos_max(radius: f32, d2: f32) -> f32 {
    (1.0 - radius * radius / d2).max(0.0).sqrt()
}

#[inline]
pub(super) fn sample(
    power: Rgb,
    c: Vec3,
    r: f32,
    p: Vec3,
    point: Vec3,
    d: Distribution,
) -> Option<LightSample> {
    let u = unit_square(point, d);
    let to_c = c - p;
    let d2 = to_c.length_squared();
    if d2 <= r * r {
        let n = square_to_uniform_sphere(u);
        return area_sample(power, p, c + r * n, n, 4.0 * PI * r * r, true);
    }
    let d = d2.sqrt();
    let cos_max = cos_max(r, d2);
    let frame = Frame::from_normal(to_c / d);
    let w = frame.to_world(square_to_uniform_cone(u, cos_max));
    // Distance to the near side of the sphere along w (clamped to the
    // tangent point when rounding puts w just outside the cone).
    let b = w.dot(to_c);
    let disc = (r * r - (d2 - b * b)).max(0.0);
    let target = p + (b - disc.sqrt()) * w;
    Some(LightSample {
        target,
        dir: (target - p).normalize_or_zero(),
        weight: power * (2.0 * PI * (1.0 - cos_max)),
        pdf: 1.0 / (2.0 * PI * (1.0 - cos_max)),
    })
}

/// The solid-angle density of [`sample`] drawing a point of the sphere seen
/// at `cos_l` (to its outward normal) and squared distance `r2` from `p`.
pub(super) fn pdf(p: Vec3, c: Vec3, radius: f32, cos_l: f32, r2: f32) -> f32 {
    let d2 = (c - p).length_squared();
    if d2 <= radius * radius {
        return area_pdf(cos_l.abs(), r2, 4.0 * PI * radius * radius);
    }
    1.0 / (2.0 * PI * (1.0 - cos_max(radius, d2)))
}
