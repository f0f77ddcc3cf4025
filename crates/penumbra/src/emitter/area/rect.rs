//! A rectangle light (a parallelogram), one-sided, emitting along its normal
//! with uniform radiance (a textured one goes through the portable path).
//! Sampled uniformly over its area; a four-wide kernel prepares four
//! samples at once with the portable path's operations.

use glam::Vec4;

use crate::emitter::sample::LightSamples4;
use crate::geometry::quad::Quad;
use crate::math::{Rgb, Vec3};

/// [`Shape::sample`](crate::geometry::Shape::sample) of a rectangle and
/// the emitter's weight, for four points at once, lane by lane the same bits (the same
/// operations in the same order, with no fused ones). Prepared one by one, a
/// set of 64 shadow rays spends a quarter of its time on them, mostly waiting
/// on the divisions.
#[inline(always)]
pub(super) fn sample4(power: Rgb, q: &Quad, p: &[Vec3; 4], points: &[Vec3; 4]) -> LightSamples4 {
    // `unit_square` and `Quad::point`, lane-wise.
    let square = |c: Vec4| {
        let max = Vec4::splat(1.0 - f32::EPSILON);
        (0.5 * (c + Vec4::ONE)).clamp(Vec4::ZERO, max)
    };
    let u = square(Vec4::from_array(points.map(|p| p.x)));
    let v = square(Vec4::from_array(points.map(|p| p.y)));
    let (o, eu, ev) = (
        q.origin.to_array(),
        q.edge_u.to_array(),
        q.edge_v.to_array(),
    );
    let target: [Vec4; 3] = std::array::from_fn(|k| o[k] + u * eu[k] + v * ev[k]);
    // `area_sample`, lane-wise.
    let to: [Vec4; 3] = std::array::from_fn(|k| target[k] - Vec4::from_array(p.map(|p| p[k])));
    let r2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
    let r = r2.sqrt();
    let n = q.normal;
    let cos_l = (n.x * -to[0] + n.y * -to[1] + n.z * -to[2]) / r;
    let valid = (cos_l.cmpgt(Vec4::ZERO) & r2.cmpgt(Vec4::ZERO)).bitmask();
    let inv = Vec4::ONE / r;
    // `power * (cos_l * area / r2)`, channel by channel.
    let scale = cos_l * q.area() / r2;
    LightSamples4 {
        target,
        dir: to.map(|c| c * inv),
        weight: power.to_array().map(|c| c * scale),
        pdf: r2 / (cos_l * q.area()),
        valid,
    }
}
