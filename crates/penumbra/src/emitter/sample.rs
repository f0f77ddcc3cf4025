//! What sampling an emitter gives, and the uniform area sampling the
//! area lights share.

use glam::Vec4;

use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_disk_concentric;

/// Where an emitter is sampled from: a shading point, and the time of the
/// ray that reached it (a moving light is sampled where it is then).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    pub p: Vec3,
    pub time: f32,
}

impl Reference {
    pub fn new(p: Vec3, time: f32) -> Reference {
        Reference { p, time }
    }
}

/// Where to send a shadow ray and what it brings if unoccluded.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    pub target: Vec3,
    /// Unit direction from the shading point to `target` (what
    /// `normalize_or_zero` gives), kept so that callers need not recompute it.
    pub dir: Vec3,
    pub weight: Rgb,
    /// The solid-angle density the target was drawn with, for weighing the
    /// sample against other strategies (multiple importance sampling); 0
    /// for a point light and for the thesis model, whose targets are not
    /// drawn from a density over the light's surface.
    pub pdf: f32,
}

/// Four light samples, one per lane, as a four-wide kernel gives them:
/// coordinates lane-wise (x, y, z).
#[derive(Clone, Copy, Debug)]
pub(super) struct LightSamples4 {
    pub target: [Vec4; 3],
    /// Unit directions from the shading point, as [`LightSample::dir`].
    pub dir: [Vec4; 3],
    /// Per lane, [`LightSample::weight`]: red, green and blue.
    pub weight: [Vec4; 3],
    /// Per lane, [`LightSample::pdf`].
    pub pdf: Vec4,
    /// Bit `i` set if lane `i` gives a sample (where `sample` gives `Some`).
    pub valid: u32,
}

impl LightSamples4 {
    /// The four samples, lane by lane.
    #[inline(always)]
    pub(super) fn lanes(&self) -> [Option<LightSample>; 4] {
        let v3 = |v: &[Vec4; 3], l: usize| Vec3::new(v[0][l], v[1][l], v[2][l]);
        std::array::from_fn(|l| {
            (self.valid >> l & 1 != 0).then(|| LightSample {
                target: v3(&self.target, l),
                dir: v3(&self.dir, l),
                weight: Rgb::from(v3(&self.weight, l).to_array()),
                pdf: self.pdf[l],
            })
        })
    }
}

/// Uniform area sampling of a one-sided light (of a sphere, two-sided when
/// `two_sided`): weight = L · cos θ_light · A / r².
#[inline]
pub(super) fn area_sample(
    power: Rgb,
    p: Vec3,
    target: Vec3,
    n: Vec3,
    area: f32,
    two_sided: bool,
) -> Option<LightSample> {
    let to = target - p;
    let r2 = to.length_squared();
    let r = r2.sqrt();
    let cos_l = n.dot(-to) / r;
    let cos_l = if two_sided { cos_l.abs() } else { cos_l };
    if !(cos_l > 0.0 && r2 > 0.0) {
        return None;
    }
    Some(LightSample {
        target,
        // `normalize_or_zero`'s own operations, so the same bits.
        dir: to * r.recip(),
        weight: power * (cos_l * area / r2),
        pdf: r2 / (cos_l * area),
    })
}

/// A ray leaving an emitter, drawn for light tracing (Mitsuba's
/// `sample_ray`): where it starts, where it goes, and the power it
/// carries, `Le · cos θ / (p(origin) · p(direction))` per colour channel
/// (the cosine at the surface it leaves, 1 for a point or from infinity).
#[derive(Clone, Copy, Debug)]
pub struct EmittedRay {
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    pub weight: Rgb,
    /// The normal of the surface it leaves (which the ray is offset
    /// along); `None` for a point and from infinity.
    pub normal: Option<Vec3>,
}

/// A point drawn on an emitter's surface (Mitsuba's `sample_position`):
/// where, the side it emits toward, and the inverse of its area density.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    pub p: Vec3,
    pub n: Vec3,
    /// Its surface coordinates (what a textured emitter is looked up at).
    pub uv: Vec2,
    /// `1 / p(p)`: the area for a uniform draw.
    pub inv_pdf: f32,
}

/// A ray arriving from infinity along `-to` (`to` the unit direction toward
/// the emitter, drawn with solid-angle density `pdf`, bringing radiance
/// `l`), entering the scene's bounding sphere `(center, radius)`: its origin
/// drawn uniformly on the disk of the sphere's radius facing it, beyond the
/// sphere, for the point `u` of the unit square (as Mitsuba's emitters at
/// infinity draw their rays). The weight is `l / pdf · π r²`.
pub(super) fn ray_from_infinity(
    to: Vec3,
    l: Rgb,
    pdf: f32,
    u: Vec2,
    (center, radius): (Vec3, f32),
) -> Option<EmittedRay> {
    if (pdf <= 0.0 || pdf.is_nan()) || (radius <= 0.0 || radius.is_nan()) {
        return None;
    }
    let d = square_to_disk_concentric(u) * radius;
    let frame = Frame::from_normal(to);
    let origin = center + to * radius + frame.to_world(Vec3::new(d.x, d.y, 0.0));
    Some(EmittedRay {
        origin,
        dir: -to,
        weight: l * (std::f32::consts::PI * radius * radius / pdf),
        normal: None,
    })
}
