//! Lights and the two penumbra models.
//!
//! A light is sampled by handing it one distribution point per shadow ray
//! (lights never own a random generator). It answers with the shadow ray's
//! target point and a weight such that the reflected radiance is
//! `brdf · weight · cos θ` at the receiver, when the ray reaches the target.
//!
//! * `thesis` (§3.3): the target is the light's centre moved on the plane
//!   facing the shading point by the distribution (radius = light size), and
//!   each ray is shaded as if the light's whole power came from that point.
//!   With one grid ray this is the classic Whitted shadow ray to the centre.
//! * `surface`: the target lies on the light's real surface and the weight
//!   carries the geometry term and the sampling pdf, so the average converges
//!   to the exact direct illumination (what pbrt or Mitsuba compute).

use std::f32::consts::PI;

use glam::Vec4;

use crate::geometry::quad::Quad;
use crate::material::{EffectSpec, Rgb};
use crate::math::{Frame, Vec3};
use crate::sampling::points::{end_point, unit_disk, unit_square};
use crate::sampling::warp::{square_to_uniform_cone, square_to_uniform_sphere};
use crate::sampling::Distribution;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PenumbraModel {
    Thesis,
    Surface,
}

#[derive(Clone, Copy, Debug)]
pub enum LightShape {
    /// Emits `intensity` (W/sr per channel) in every direction.
    Point {
        position: Vec3,
    },
    /// One-sided parallelogram emitting along its normal.
    Rect(Quad),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// One-sided disk emitting along `frame.n`.
    Disk {
        center: Vec3,
        frame: Frame,
        radius: f32,
    },
}

#[derive(Clone, Debug)]
pub struct Light {
    pub shape: LightShape,
    /// Intensity for a point light, radiance for area lights.
    pub power: Rgb,
    pub model: PenumbraModel,
    pub shadow: EffectSpec,
}

/// Where to send a shadow ray and what it brings if unoccluded.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    pub target: Vec3,
    /// Unit direction from the shading point to `target` (what
    /// `normalize_or_zero` gives), kept so that callers need not recompute it.
    pub dir: Vec3,
    pub weight: Rgb,
}

/// Four light samples, one per lane, as [`Light::sample4`] gives them:
/// coordinates lane-wise (x, y, z).
#[derive(Clone, Copy, Debug)]
pub struct LightSamples4 {
    pub target: [Vec4; 3],
    /// Unit directions from the shading point, as [`LightSample::dir`].
    pub dir: [Vec4; 3],
    /// Per lane, [`LightSample::weight`] is `power · scale`.
    pub scale: Vec4,
    /// Bit `i` set if lane `i` gives a sample (where `sample` gives `Some`).
    pub valid: u32,
}

impl Light {
    pub fn center(&self) -> Vec3 {
        match self.shape {
            LightShape::Point { position } => position,
            LightShape::Rect(q) => q.center(),
            LightShape::Sphere { center, .. } | LightShape::Disk { center, .. } => center,
        }
    }

    /// A point light has no extent: every shadow ray would be identical.
    pub fn is_delta(&self) -> bool {
        matches!(self.shape, LightShape::Point { .. })
    }

    /// Shadow rays actually traced per shading point.
    pub fn shadow_rays(&self) -> u32 {
        if self.is_delta() {
            1
        } else {
            self.shadow.rays
        }
    }

    /// The thesis's light size: the radius of the distribution around the
    /// centre. A rectangle uses half the side of the square of equal area.
    pub fn size(&self) -> f32 {
        match self.shape {
            LightShape::Point { .. } => 0.0,
            LightShape::Rect(q) => 0.5 * q.area().sqrt(),
            LightShape::Sphere { radius, .. } | LightShape::Disk { radius, .. } => radius,
        }
    }

    /// Radiance leaving the light's surface toward `-dir` at a point with
    /// outward normal `n` (area lights are one-sided except spheres).
    pub fn emitted(&self, n: Vec3, dir: Vec3) -> Rgb {
        match self.shape {
            LightShape::Point { .. } => Rgb::ZERO,
            LightShape::Sphere { .. } => self.power,
            LightShape::Rect(_) | LightShape::Disk { .. } => {
                if n.dot(dir) < 0.0 {
                    self.power
                } else {
                    Rgb::ZERO
                }
            }
        }
    }

    /// Samples the light from shading point `p` with one distribution point.
    pub fn sample(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        match self.model {
            _ if self.is_delta() => self.sample_thesis(p, Vec3::ZERO, d),
            PenumbraModel::Thesis => self.sample_thesis(p, point, d),
            PenumbraModel::Surface => self.sample_surface(p, point, d),
        }
    }

    /// True if [`sample4`](Self::sample4) has a four-wide path for points
    /// of `d`: a rectangle sampled on its surface by a square distribution.
    pub fn four_wide(&self, d: Distribution) -> bool {
        let rect = matches!(self.shape, LightShape::Rect(_));
        rect && self.model == PenumbraModel::Surface && d != Distribution::Random
    }

    /// [`sample`](Self::sample) for four distribution points at once, seen
    /// from the shading points `p` (one per lane: one point four times for a
    /// set, or the hits of four camera rays), lane by lane the same bits
    /// (the same operations in the same order, with no fused ones), or
    /// `None` where there is no [four-wide](Self::four_wide) path. It exists
    /// for the common case: prepared one by one, a set of 64 shadow rays spends
    /// a quarter of its time on them, mostly waiting on the divisions.
    #[inline]
    pub fn sample4(
        &self,
        p: &[Vec3; 4],
        points: &[Vec3; 4],
        d: Distribution,
    ) -> Option<LightSamples4> {
        let LightShape::Rect(q) = self.shape else {
            return None;
        };
        if !self.four_wide(d) {
            return None;
        }
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
        Some(LightSamples4 {
            target,
            dir: to.map(|c| c * inv),
            scale: cos_l * q.area() / r2,
            valid,
        })
    }

    /// Intensity toward direction `w` (unit, from the light) of the light
    /// collapsed to a point, as the thesis shades every shadow ray.
    fn point_intensity(&self, w: Vec3) -> Rgb {
        match self.shape {
            LightShape::Point { .. } => self.power,
            LightShape::Rect(q) => self.power * (q.area() * q.normal.dot(w).max(0.0)),
            LightShape::Sphere { radius, .. } => self.power * (PI * radius * radius),
            LightShape::Disk { frame, radius, .. } => {
                self.power * (PI * radius * radius * frame.n.dot(w).max(0.0))
            }
        }
    }

    fn sample_thesis(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        let c = self.center();
        let axis = (c - p).normalize_or_zero();
        let target = end_point(c, axis, point, self.size(), d);
        let to = target - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        let weight = self.point_intensity(-to / r2.sqrt()) / r2;
        Some(LightSample {
            target,
            dir: to.normalize_or_zero(),
            weight,
        })
    }

    fn sample_surface(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        match self.shape {
            LightShape::Point { .. } => self.sample_thesis(p, Vec3::ZERO, d),
            LightShape::Rect(q) => {
                let u = unit_square(point, d);
                self.area_sample(p, q.point(u.x, u.y), q.normal, q.area())
            }
            LightShape::Disk {
                center,
                frame,
                radius,
            } => {
                let u = unit_disk(point, d) * radius;
                let target = center + u.x * frame.u + u.y * frame.v;
                self.area_sample(p, target, frame.n, PI * radius * radius)
            }
            LightShape::Sphere { center, radius } => {
                self.sphere_sample(p, center, radius, unit_square(point, d))
            }
        }
    }

    /// Uniform area sampling: weight = L · cos θ_light · A / r².
    fn area_sample(&self, p: Vec3, target: Vec3, n: Vec3, area: f32) -> Option<LightSample> {
        let to = target - p;
        let r2 = to.length_squared();
        let r = r2.sqrt();
        let cos_l = n.dot(-to) / r;
        let cos_l = if matches!(self.shape, LightShape::Sphere { .. }) {
            cos_l.abs()
        } else {
            cos_l
        };
        if !(cos_l > 0.0 && r2 > 0.0) {
            return None;
        }
        Some(LightSample {
            target,
            // `normalize_or_zero`'s own operations, so the same bits.
            dir: to * r.recip(),
            weight: self.power * (cos_l * area / r2),
        })
    }

    /// Uniform sampling of the cone the sphere subtends (pdf 1/(2π(1−cos θmax))),
    /// so that every sample hits the visible cap; inside the sphere, area sampling.
    fn sphere_sample(&self, p: Vec3, c: Vec3, r: f32, u: crate::math::Vec2) -> Option<LightSample> {
        let to_c = c - p;
        let d2 = to_c.length_squared();
        if d2 <= r * r {
            let n = square_to_uniform_sphere(u);
            return self.area_sample(p, c + r * n, n, 4.0 * PI * r * r);
        }
        let d = d2.sqrt();
        let cos_max = (1.0 - r * r / d2).max(0.0).sqrt();
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
            weight: self.power * (2.0 * PI * (1.0 - cos_max)),
        })
    }
}
