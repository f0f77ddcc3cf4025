//! Emitters: what lights a scene, built once per scene and shared by every
//! worker.
//!
//! An emitter is sampled from a shading point by handing it one
//! distribution point per shadow ray (emitters never own random numbers).
//! It answers with the shadow ray's target point and a weight such that the
//! reflected radiance is `bsdf · weight · cos θ` at the receiver when the
//! ray reaches the target ([`Emitter::sample`]); [`Emitter::pdf`] gives the
//! density it draws a target with, [`Emitter::eval`] the radiance a ray
//! that hits its surface sees, [`Emitter::eval_miss`] what a ray that hits
//! nothing sees of it. For light tracing, every emitter draws rays leaving
//! it ([`Emitter::sample_ray`]: origin, direction and the power carried),
//! and an emitter with a surface draws points of it
//! ([`Emitter::sample_position`]).
//!
//! | emitter | where | what |
//! |---|---|---|
//! | [`point`] | at a position | intensity in every direction; no surface |
//! | [`spot`] | at a position | intensity in a cone, falling off toward its edge; no surface |
//! | [`directional`] | at infinity, one direction | irradiance along one direction (a sun); not seen by rays |
//! | [`area`] | on a shape (rectangle, sphere, disk, mesh) | radiance from the surface, uniform or a texture looked up at its `(u, v)`; two penumbra models |
//! | [`constant`] | at infinity | the background: radiance from every direction |
//! | [`envmap`] | at infinity | radiance from every direction, read from an equirectangular image; importance-sampled |
//! | [`sky`] | at infinity | a gradient sky and a sun disc, computed into an `envmap` when the scene is built |
//!
//! Each emitter implements [`EmitterModel`]; the closed enum [`Emitter`]
//! and its dispatch are made by the `emitters!` list in this file, one
//! line per emitter, one match per question, inlined into the shading
//! loops.

pub mod area;
pub mod bounds;
pub mod choice;
pub mod constant;
pub mod directional;
pub mod envmap;
mod model;
pub mod point;
pub mod projector;
mod sample;
pub mod sky;
pub mod spot;

pub use area::{Area, PenumbraModel};
pub use constant::Constant;
pub use directional::Directional;
pub use envmap::Envmap;
pub use model::{EmitterModel, EmitterPlugin};
pub use point::Point;
pub use projector::Projector;
pub use sample::{EmittedRay, LightSample, Reference, SurfacePoint};
pub use sky::Sky;
pub use spot::Spot;

use crate::texture::Textures;

use crate::description::mitsuba::Plugin;
use crate::description::{Invalid, Props, Schema};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::Distribution;

/// Makes [`Emitter`], the enum of the emitters listed (each a variant
/// named as its type), and its dispatch through [`EmitterModel`].
macro_rules! emitters {
    ($($variant:ident,)*) => {
        /// An emitter, ready to be sampled.
        #[derive(Clone, Debug)]
        pub enum Emitter {
            $($variant($variant),)*
        }

        $(impl From<$variant> for Emitter {
            fn from(e: $variant) -> Emitter {
                Emitter::$variant(e)
            }
        })*

        impl Emitter {
            /// True for an emitter without extent (see [`EmitterModel::is_delta`]).
            #[inline]
            pub fn is_delta(&self) -> bool {
                match self {
                    $(Emitter::$variant(e) => e.is_delta(),)*
                }
            }

            /// True for an emitter at infinity that rays that hit nothing
            /// see (see [`EmitterModel::is_infinite`]).
            #[inline]
            pub fn is_infinite(&self) -> bool {
                match self {
                    $(Emitter::$variant(e) => e.is_infinite(),)*
                }
            }

            /// Fits the emitter to the scene's bounding sphere: a
            /// directional light's shadow rays leave it.
            pub fn fit(&mut self, center: Vec3, radius: f32) {
                match self {
                    $(Emitter::$variant(e) => e.fit(center, radius),)*
                }
            }

            /// The power it emits (see [`EmitterModel::power`]).
            pub fn power(&self, radius: f32) -> f32 {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::power(e, radius),)*
                }
            }

            /// Its bounds for a light BVH; `None` for an emitter at infinity.
            pub fn bounds(&self) -> Option<bounds::LightBounds> {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::bounds(e),)*
                }
            }

            /// Radiance leaving the emitter's surface toward `-dir` at a
            /// point with geometric normal `n` and surface coordinates `uv`.
            #[inline]
            pub fn eval(&self, n: Vec3, uv: Vec2, dir: Vec3) -> Rgb {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::eval(e, n, uv, dir),)*
                }
            }

            /// Radiance arriving along `dir` from infinity (what a ray that
            /// hits nothing sees of this emitter).
            #[inline]
            pub fn eval_miss(&self, dir: Vec3) -> Rgb {
                match self {
                    $(Emitter::$variant(e) => e.eval_miss(dir),)*
                }
            }

            /// Samples the emitter for a batch of distribution points:
            /// sample `k` seen from the shading point `at(k)` (at its ray's
            /// time) with the point
            /// `points[k]`, appended to `out` (`None` where the point gives
            /// no sample: on the back of the light, say). The one way an
            /// emitter is sampled. A rectangle sampled on its surface by a
            /// square distribution takes its points four at a time through
            /// its kernel, which gives lane by lane the bits of the portable
            /// form (the same operations in the same order, with no fused
            /// ones); the rest of a batch, and every other emitter, go point
            /// by point.
            pub fn sample(
                &self,
                at: impl Fn(usize) -> Reference,
                points: &[Vec3],
                d: Distribution,
                out: &mut Vec<Option<LightSample>>,
            ) {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::sample(e, at, points, d, out),)*
                }
            }

            /// One sample of [`sample`](Self::sample), the portable form.
            pub fn sample_one(&self, r: Reference, point: Vec3, d: Distribution) -> Option<LightSample> {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::sample_one(e, r, point, d),)*
                }
            }

            /// For an emitter at infinity, a direction toward it (see
            /// [`EmitterModel::sample_direction`]). The integrators that
            /// follow paths sample the background with it.
            pub fn sample_direction(&self, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
                match self {
                    $(Emitter::$variant(e) => e.sample_direction(u),)*
                }
            }

            /// The solid-angle density with which
            /// [`sample_direction`](Self::sample_direction) draws `dir`; 0
            /// for emitters not at infinity.
            pub fn pdf_direction(&self, dir: Vec3) -> f32 {
                match self {
                    $(Emitter::$variant(e) => e.pdf_direction(dir),)*
                }
            }

            /// A ray leaving the emitter, for light tracing (see
            /// [`EmitterModel::sample_ray`]).
            pub fn sample_ray(
                &self,
                u_pos: Vec2,
                u_dir: Vec2,
                time: f32,
                sphere: (Vec3, f32),
            ) -> Option<EmittedRay> {
                match self {
                    $(Emitter::$variant(e) => e.sample_ray(u_pos, u_dir, time, sphere),)*
                }
            }

            /// A point of the emitter's surface (see
            /// [`EmitterModel::sample_position`]).
            pub fn sample_position(&self, u: Vec2, time: f32) -> Option<SurfacePoint> {
                match self {
                    $(Emitter::$variant(e) => e.sample_position(u, time),)*
                }
            }

            /// The solid-angle density with which [`sample`](Self::sample)
            /// draws `target` (see [`EmitterModel::pdf`]).
            pub fn pdf(&self, r: Reference, target: Vec3, n: Vec3) -> f32 {
                match self {
                    $(Emitter::$variant(e) => EmitterModel::pdf(e, r, target, n),)*
                }
            }
        }
    };
}

// The emitters: one line each.
emitters! {
    Point,
    Area,
    Constant,
    Spot,
    Projector,
    Directional,
    Envmap,
}

/// Makes the registry of the emitters a scene names by itself: their
/// schemas, their plugins as the readers see them (the `area` emitter,
/// which shapes carry, among them) and [`build`].
macro_rules! plugins {
    ($($plugin:ident,)*) => {
        /// The emitters a scene names by itself, in the order messages
        /// list them.
        pub const SCHEMAS: &[&Schema] = &[$(&$plugin::SCHEMA,)*];

        /// The emitters as the readers see them: those a scene names by
        /// itself, then the `area` emitter a shape carries.
        pub const PLUGINS: &[Plugin] = &[
            $(Plugin::new(&$plugin::SCHEMA, $plugin::MITSUBA),)*
            Plugin::new(&area::SCHEMA, area::MITSUBA),
        ];

        /// The emitter `plugin` of the parameters `p` (files relative to
        /// `textures.base_dir`, textures read through `textures`); `None`
        /// for a name no emitter of [`SCHEMAS`] has.
        pub fn build(plugin: &str, p: &Props, textures: &Textures) -> Option<Result<Emitter, Invalid>> {
            $(if plugin == $plugin::SCHEMA.plugin {
                return Some(<$plugin as EmitterPlugin>::build(p, textures).map(Emitter::from));
            })*
            None
        }
    };
}

// The emitters a scene names by itself: one line each.
plugins! {
    Point,
    Constant,
    Spot,
    Projector,
    Directional,
    Envmap,
    Sky,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::quad::Quad;
    use crate::geometry::surface::tests::{still, triangles};
    use crate::geometry::{Disk, Shape, Sphere, Surface};
    use crate::math::Frame;
    use crate::sampling::Rng;

    fn area(surface: Surface) -> Emitter {
        Emitter::Area(Area::new(
            surface,
            crate::texture::Texture::Constant(Rgb::splat(2.0)),
            PenumbraModel::Surface,
        ))
    }

    /// For each area light, every sample's weight is `L / pdf` at its target
    /// (in solid angle), so that the estimator of direct light is unbiased,
    /// and the sample carries that pdf (what multiple importance sampling
    /// weighs it by).
    #[test]
    fn weights_are_radiance_over_pdf() {
        let at = Reference::new(Vec3::new(0.3, 0.0, -0.2), 0.0);
        let mesh = triangles(&[
            [
                Vec3::new(-0.5, 2.0, -0.5),
                Vec3::new(0.5, 2.0, -0.5),
                Vec3::new(-0.5, 2.0, 0.5),
            ],
            [
                Vec3::new(0.5, 2.2, -0.5),
                Vec3::new(0.5, 2.2, 0.5),
                Vec3::new(-0.5, 2.2, 0.5),
            ],
        ]);
        let lights = [
            area(still(Shape::Quad(Quad::new(
                Vec3::new(-0.5, 2.0, -0.5),
                Vec3::X,
                Vec3::Z,
            )))),
            area(still(Shape::Disk(Disk::new(
                Vec3::new(0.0, 2.0, 0.0),
                Frame::from_normal(-Vec3::Y),
                0.6,
            )))),
            area(still(Shape::Sphere(Sphere::new(
                Vec3::new(0.5, 2.5, 0.0),
                0.5,
            )))),
            area(mesh),
            area(still(Shape::Cylinder(
                crate::geometry::Cylinder::new(
                    Vec3::new(-1.0, 2.0, 0.0),
                    Vec3::new(1.0, 2.0, 0.0),
                    0.3,
                )
                .unwrap(),
            ))),
        ];
        let mut rng = Rng::new(17);
        for e in &lights {
            let Emitter::Area(a) = e else { unreachable!() };
            let mut found = 0;
            for _ in 0..2000 {
                let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                let Some(s) = e.sample_one(at, point, Distribution::Random) else {
                    continue;
                };
                let shape = a.surface.shape();
                let n = if let Some(ball) = shape.as_sphere() {
                    (s.target - ball.center).normalize()
                } else if let Some(c) = shape.as_cylinder() {
                    let d = s.target - c.base;
                    (d - d.dot(c.frame.n) * c.frame.n).normalize()
                } else if let Some((n, _)) = shape.plane() {
                    n
                } else {
                    // Both triangles face down.
                    -Vec3::Y
                };
                let pdf = e.pdf(at, s.target, n);
                assert!(pdf > 0.0);
                assert!(
                    (s.pdf - pdf).abs() < 2e-3 * pdf,
                    "{e:?}: {} vs {pdf}",
                    s.pdf
                );
                let want = 2.0 / pdf;
                assert!(
                    (s.weight.r - want).abs() < 2e-3 * want,
                    "{e:?}: {} vs {want}",
                    s.weight.r
                );
                found += 1;
            }
            // Under half of a tube faces a point outside it.
            let tube = a.surface.shape().as_cylinder().is_some();
            assert!(found > if tube { 600 } else { 1000 }, "{found}");
        }
    }

    /// The rays an emitter draws for light tracing carry its power: the
    /// mean of their weights (mean over the colour channels) is what
    /// `power` says, for every emitter (a projector's weight is its
    /// image's value times a constant), and every ray leaves toward the
    /// side the emitter lights: an area light along its normal, a spot
    /// inside its cone, a light at infinity from beyond the scene's sphere
    /// into it.
    #[test]
    fn rays_carry_the_power() {
        let sphere = (Vec3::new(0.5, -1.0, 2.0), 3.0);
        let spot = Spot::new(
            Vec3::ZERO,
            Vec3::new(0.0, -1.0, 0.2),
            Rgb::splat(2.0),
            40.0,
            25.0,
        );
        let mut directional = Directional::new(Vec3::new(0.3, -1.0, 0.1), Rgb::new(1.0, 2.0, 3.0));
        directional.fit(sphere.0, sphere.1);
        let map: Vec<Rgb> = (0..32 * 16)
            .map(|i| Rgb::splat(0.2 + (i % 7) as f32 + 0.1 * (i / 32) as f32))
            .collect();
        let envmap = Envmap::new(32, 16, map, crate::math::Mat3::IDENTITY, false);
        let emitters = [
            Emitter::Point(Point {
                position: Vec3::ONE,
                intensity: Rgb::new(1.0, 2.0, 0.5),
            }),
            Emitter::Spot(spot),
            Emitter::Directional(directional),
            Emitter::Constant(Constant {
                radiance: Rgb::splat(0.7),
            }),
            Emitter::Envmap(envmap),
            area(still(Shape::Quad(Quad::new(
                Vec3::new(-0.5, 2.0, -0.5),
                Vec3::X,
                Vec3::Z,
            )))),
            area(still(Shape::Sphere(Sphere::new(
                Vec3::new(0.5, 2.5, 0.0),
                0.5,
            )))),
            area(still(Shape::Disk(Disk::new(
                Vec3::new(0.0, 2.0, 0.0),
                Frame::from_normal(-Vec3::Y),
                0.6,
            )))),
        ];
        let n = 256;
        for e in &emitters {
            let mut sum = 0f64;
            let mut rng = Rng::new(9);
            for i in 0..n * n {
                // Stratified directions, random origins.
                let u_dir = Vec2::new(
                    ((i % n) as f32 + rng.next_f32()) / n as f32,
                    ((i / n) as f32 + rng.next_f32()) / n as f32,
                );
                let u_pos = Vec2::new(rng.next_f32(), rng.next_f32());
                let Some(r) = e.sample_ray(u_pos, u_dir, 0.0, sphere) else {
                    continue;
                };
                assert!((r.dir.length() - 1.0).abs() < 1e-4, "{e:?}");
                if let Some(nl) = r.normal {
                    assert!(r.dir.dot(nl) >= 0.0, "{e:?}");
                }
                if let Emitter::Spot(s) = e {
                    assert!(s.falloff(r.dir) > 0.0);
                }
                if e.is_infinite() || matches!(e, Emitter::Directional(_)) {
                    let from = r.origin - sphere.0;
                    assert!(from.length() >= sphere.1 * 0.999, "{e:?}");
                    assert!(from.dot(r.dir) < 0.0, "{e:?}");
                }
                sum += f64::from(bounds::mean(r.weight));
            }
            let mean = sum / f64::from(n * n);
            let want = f64::from(e.power(sphere.1));
            assert!(
                (mean - want).abs() < 0.01 * want,
                "{e:?}: rays carry {mean}, power {want}"
            );
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
            Shape::Quad(rect),
            Shape::Sphere(Sphere::new(Vec3::new(0.5, 2.5, 0.0), 0.5)),
        ];
        let point = Emitter::Point(Point {
            position: Vec3::new(0.0, 3.0, 0.0),
            intensity: Rgb::splat(2.0),
        });
        let mut lights = vec![(point, false)];
        for shape in shapes {
            for model in [PenumbraModel::Surface, PenumbraModel::Thesis] {
                let Emitter::Area(mut a) = area(still(shape.clone())) else {
                    unreachable!()
                };
                a.model = model;
                lights.push((Emitter::Area(a), true));
            }
        }
        let mut rng = Rng::new(23);
        let (mut kernel, mut valid, mut out) = (0, 0, Vec::new());
        let bits = |s: &Option<LightSample>| {
            s.map(|s| {
                let pdf = Vec3::splat(s.pdf);
                [s.target, s.dir, Vec3::from(s.weight.to_array()), pdf].map(|v| v.to_array())
            })
            .map(|v| v.map(|c| c.map(f32::to_bits)))
        };
        for (light, _) in &lights {
            for d in Distribution::ALL {
                if let Emitter::Area(a) = light {
                    kernel += usize::from(a.four_wide(d).is_some());
                }
                for n in 0..200 {
                    let mut v = |lo: f32, hi: f32, z: f32| {
                        Vec3::new(rng.range(lo, hi), rng.range(-1.0, hi), rng.range(-z, z))
                    };
                    let p: Vec<Vec3> = (0..n % 10).map(|_| v(-3.0, 4.0, 3.0)).collect();
                    let points: Vec<Vec3> = p.iter().map(|_| v(-1.2, 1.2, 1.0)).collect();
                    out.clear();
                    light.sample(|k| Reference::new(p[k], 0.0), &points, d, &mut out);
                    assert_eq!(out.len(), p.len());
                    for ((p, point), got) in p.iter().zip(&points).zip(&out) {
                        let want = light.sample_one(Reference::new(*p, 0.0), *point, d);
                        assert_eq!(bits(got), bits(&want), "{light:?} {d:?}");
                        valid += usize::from(got.is_some());
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
