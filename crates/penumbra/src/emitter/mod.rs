//! Light sources: what a light sends toward a point, built from the scene's
//! light records, and the two penumbra models.
//!
//! An emitter is sampled by handing it one distribution point per shadow ray
//! (emitters never own random numbers). It answers with the shadow ray's
//! target point and a weight such that the reflected radiance is
//! `brdf · weight · cos θ` at the receiver, when the ray reaches the target;
//! [`Emitter::pdf`] gives the density the surface model draws a target with,
//! and [`Emitter::emitted`] the radiance a ray that hits the light sees.
//!
//! * `thesis` (§3.3): the target is the light's centre moved on the plane
//!   facing the shading point by the distribution (radius = light size), and
//!   each ray is shaded as if the light's whole power came from that point.
//!   With one grid ray this is the classic Whitted shadow ray to the centre.
//! * `surface`: the target lies on the light's real surface and the weight
//!   carries the geometry term and the sampling pdf, so the average converges
//!   to the exact direct illumination (what pbrt or Mitsuba compute).
//!
//! One file per kind of light (point, rectangle, sphere, disk) holds its
//! surface sampling; this file dispatches, a closed set with one match per
//! question.

mod disk;
mod point;
mod rect;
mod sample;
mod sphere;

pub use sample::LightSample;

use crate::math::{Rgb, Vec3};
use crate::sampling::points::end_point;
use crate::sampling::Distribution;
use crate::scene::{EffectSpec, Light, LightShape, PenumbraModel};
use sample::area_pdf;

/// A light, ready to be sampled.
#[derive(Clone, Debug)]
pub struct Emitter {
    light: Light,
}

impl Emitter {
    pub fn new(light: &Light) -> Emitter {
        Emitter {
            light: light.clone(),
        }
    }

    /// The record it was built from.
    pub fn light(&self) -> &Light {
        &self.light
    }

    /// Rays per shadow set and their distribution.
    #[inline]
    pub fn shadow(&self) -> EffectSpec {
        self.light.shadow
    }

    pub fn center(&self) -> Vec3 {
        match self.light.shape {
            LightShape::Point { position } => position,
            LightShape::Rect(q) => q.center(),
            LightShape::Sphere { center, .. } | LightShape::Disk { center, .. } => center,
        }
    }

    /// A point light has no extent: every shadow ray would be identical.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.light.is_delta()
    }

    /// Shadow rays actually traced per shading point.
    #[inline]
    pub fn shadow_rays(&self) -> u32 {
        if self.is_delta() {
            1
        } else {
            self.light.shadow.rays
        }
    }

    /// The thesis's light size: the radius of the distribution around the
    /// centre. A rectangle uses half the side of the square of equal area.
    pub fn size(&self) -> f32 {
        match self.light.shape {
            LightShape::Point { .. } => 0.0,
            LightShape::Rect(q) => rect::size(&q),
            LightShape::Sphere { radius, .. } | LightShape::Disk { radius, .. } => radius,
        }
    }

    /// Radiance leaving the light's surface toward `-dir` at a point with
    /// outward normal `n` (area lights are one-sided except spheres).
    #[inline]
    pub fn emitted(&self, n: Vec3, dir: Vec3) -> Rgb {
        let power = self.light.power;
        match self.light.shape {
            LightShape::Point { .. } => Rgb::ZERO,
            LightShape::Sphere { .. } => power,
            LightShape::Rect(_) | LightShape::Disk { .. } => {
                if n.dot(dir) < 0.0 {
                    power
                } else {
                    Rgb::ZERO
                }
            }
        }
    }

    /// Samples the light for a batch of distribution points: sample `k`
    /// seen from the shading point `at(k)` with the point `points[k]`,
    /// appended to `out` (`None` where the point gives no sample: on the
    /// back of the light, say). The one way an emitter is sampled. A
    /// rectangle sampled on its surface by a square distribution takes its
    /// points four at a time through its kernel, which gives lane by lane
    /// the bits of the portable form (the same operations in the same order,
    /// with no fused ones); the rest of a batch, and every other light, go
    /// point by point.
    pub fn sample(
        &self,
        at: impl Fn(usize) -> Vec3,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        let wide = match self.light.shape {
            LightShape::Rect(q) if self.four_wide(d) => {
                let fours = points.chunks_exact(4);
                for (g, four) in fours.enumerate() {
                    let p = std::array::from_fn(|l| at(4 * g + l));
                    let four = four.try_into().expect("chunks of four");
                    out.extend(rect::sample4(self.light.power, &q, &p, four).lanes());
                }
                points.len() / 4 * 4
            }
            _ => 0,
        };
        let rest = points.iter().enumerate().skip(wide);
        out.extend(rest.map(|(k, &point)| self.sample_one(at(k), point, d)));
    }

    /// One sample of [`sample`](Self::sample): the portable form, which the
    /// rectangle's kernel is tested against.
    fn sample_one(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        match self.light.model {
            _ if self.is_delta() => self.sample_thesis(p, Vec3::ZERO, d),
            PenumbraModel::Thesis => self.sample_thesis(p, point, d),
            PenumbraModel::Surface => self.sample_surface(p, point, d),
        }
    }

    /// The solid-angle density with which the surface model draws `target`
    /// (a point of the light with outward normal `n`) from `p`; 0 for a
    /// point light and for the thesis model, whose rays are not drawn from
    /// the light's surface.
    pub fn pdf(&self, p: Vec3, target: Vec3, n: Vec3) -> f32 {
        if self.is_delta() || self.light.model == PenumbraModel::Thesis {
            return 0.0;
        }
        let to = target - p;
        let r2 = to.length_squared();
        let cos_l = n.dot(-to) / r2.sqrt();
        match self.light.shape {
            LightShape::Point { .. } => 0.0,
            LightShape::Sphere { center, radius } => sphere::pdf(p, center, radius, cos_l, r2),
            LightShape::Rect(q) => area_pdf(cos_l, r2, q.area()),
            LightShape::Disk { radius, .. } => area_pdf(cos_l, r2, disk::area(radius)),
        }
    }

    /// True if [`sample`](Self::sample) takes points of `d` four at a time
    /// through a kernel: a rectangle sampled on its surface by a square
    /// distribution.
    #[inline]
    fn four_wide(&self, d: Distribution) -> bool {
        let rect = matches!(self.light.shape, LightShape::Rect(_));
        rect && self.light.model == PenumbraModel::Surface && d != Distribution::Random
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

    /// Intensity toward direction `w` (unit, from the light) of the light
    /// collapsed to a point, as the thesis shades every shadow ray.
    fn point_intensity(&self, w: Vec3) -> Rgb {
        let power = self.light.power;
        match self.light.shape {
            LightShape::Point { .. } => point::intensity(power),
            LightShape::Rect(q) => rect::intensity(power, &q, w),
            LightShape::Sphere { radius, .. } => sphere::intensity(power, radius),
            LightShape::Disk { frame, radius, .. } => disk::intensity(power, frame.n, radius, w),
        }
    }

    fn sample_surface(&self, p: Vec3, point: Vec3, d: Distribution) -> Option<LightSample> {
        let power = self.light.power;
        match self.light.shape {
            LightShape::Point { .. } => self.sample_thesis(p, Vec3::ZERO, d),
            LightShape::Rect(q) => rect::sample(power, &q, p, point, d),
            LightShape::Disk {
                center,
                frame,
                radius,
            } => disk::sample(power, center, &frame, radius, p, point, d),
            LightShape::Sphere { center, radius } => {
                sphere::sample(power, center, radius, p, point, d)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::quad::Quad;
    use crate::math::Frame;
    use crate::sampling::Rng;

    fn emitter(shape: LightShape) -> Emitter {
        Emitter::new(&Light {
            shape,
            power: Rgb::splat(2.0),
            model: PenumbraModel::Surface,
            shadow: EffectSpec {
                rays: 16,
                distribution: Distribution::Random,
            },
        })
    }

    /// For each area light, every sample's weight is `L · / pdf` at its
    /// target (`weight = L / pdf` in solid angle), so that the estimator of
    /// direct light is unbiased.
    #[test]
    fn weights_are_radiance_over_pdf() {
        let p = Vec3::new(0.3, 0.0, -0.2);
        let lights = [
            emitter(LightShape::Rect(Quad::new(
                Vec3::new(-0.5, 2.0, -0.5),
                Vec3::X,
                Vec3::Z,
            ))),
            emitter(LightShape::Disk {
                center: Vec3::new(0.0, 2.0, 0.0),
                frame: Frame::from_normal(-Vec3::Y),
                radius: 0.6,
            }),
            emitter(LightShape::Sphere {
                center: Vec3::new(0.5, 2.5, 0.0),
                radius: 0.5,
            }),
        ];
        let mut rng = Rng::new(17);
        for e in &lights {
            let mut found = 0;
            for _ in 0..2000 {
                let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                let Some(s) = e.sample_one(p, point, Distribution::Random) else {
                    continue;
                };
                let n = match e.light().shape {
                    LightShape::Sphere { center, .. } => (s.target - center).normalize(),
                    LightShape::Rect(q) => q.normal,
                    LightShape::Disk { frame, .. } => frame.n,
                    LightShape::Point { .. } => unreachable!(),
                };
                let pdf = e.pdf(p, s.target, n);
                assert!(pdf > 0.0);
                let want = 2.0 / pdf;
                assert!(
                    (s.weight.r - want).abs() < 2e-3 * want,
                    "{e:?}: {} vs {want}",
                    s.weight.r
                );
                found += 1;
            }
            assert!(found > 1000);
        }
    }

    /// A batch's samples are, one by one, the portable samples bit for bit:
    /// where there is a kernel (a rectangle under the surface model, every
    /// square distribution), and elsewhere. Batches of 0 to 9 points (so
    /// groups of four and a rest), points inside and outside the square,
    /// shading points all around the light.
    #[test]
    fn batches_are_the_portable_samples() {
        let rect = Quad::new(Vec3::new(-0.5, 2.0, -0.5), Vec3::X, Vec3::Z);
        let shapes = [
            LightShape::Rect(rect),
            LightShape::Sphere {
                center: Vec3::new(0.5, 2.5, 0.0),
                radius: 0.5,
            },
            LightShape::Point {
                position: Vec3::new(0.0, 3.0, 0.0),
            },
        ];
        let mut rng = Rng::new(23);
        let (mut kernel, mut valid, mut out) = (0, 0, Vec::new());
        let bits = |s: &Option<LightSample>| {
            s.map(|s| [s.target, s.dir, Vec3::from(s.weight.to_array())].map(|v| v.to_array()))
                .map(|v| v.map(|c| c.map(f32::to_bits)))
        };
        for shape in shapes {
            for model in [PenumbraModel::Surface, PenumbraModel::Thesis] {
                for d in Distribution::ALL {
                    let mut light = emitter(shape);
                    light.light.model = model;
                    kernel += usize::from(light.four_wide(d));
                    for n in 0..200 {
                        let mut v = |lo: f32, hi: f32, z: f32| {
                            Vec3::new(rng.range(lo, hi), rng.range(-1.0, hi), rng.range(-z, z))
                        };
                        let p: Vec<Vec3> = (0..n % 10).map(|_| v(-3.0, 4.0, 3.0)).collect();
                        let points: Vec<Vec3> = p.iter().map(|_| v(-1.2, 1.2, 1.0)).collect();
                        out.clear();
                        light.sample(|k| p[k], &points, d, &mut out);
                        assert_eq!(out.len(), p.len());
                        for ((p, point), got) in p.iter().zip(&points).zip(&out) {
                            let want = light.sample_one(*p, *point, d);
                            assert_eq!(bits(got), bits(&want), "{shape:?} {model:?} {d:?}");
                            valid += usize::from(got.is_some());
                        }
                    }
                }
            }
        }
        assert_eq!(
            kernel,
            Distribution::ALL.len() - 1,
            "the rectangle's kernel runs"
        );
        assert!(valid > 20_000, "{valid} samples compared");
    }
}
