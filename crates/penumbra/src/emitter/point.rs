//! `point`: a point light of `intensity` (W/sr per channel) in every
//! direction. It has no surface: its one shadow ray goes to its position,
//! under both penumbra models.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `position` | vector | **required** | where it is |
//! | `intensity` | colour ≥ 0 | **required** | radiant intensity |

use crate::texture::Textures;

use super::bounds::{mean, LightBounds};
use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{EmittedRay, LightSample, Reference};
use crate::description::check::{finite3_value, nonneg3, required};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Aabb, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_uniform_sphere;
use crate::sampling::Distribution;

#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl Point {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "point",
        what: "point light",
        doc: "a point emitting the same intensity in every direction",
        mitsuba: &["point"],
        params: &[
            Param::new("position", Type::Vector, "required", "where it is"),
            Param::new(
                "intensity",
                Type::Colour,
                "required",
                "radiant intensity (W/sr per channel), ≥ 0",
            )
            .range(Range::NonNegative),
        ],
    };

    /// How Mitsuba's `point` maps onto it.
    pub const MITSUBA: Mitsuba = Mitsuba {
        differences: "`position` is the origin and `intensity` 1 when not given, as in Mitsuba",
        reads: &["to_world"],
        adapt: Some(Adapt::Node(adapt::point)),
    };

    /// The light of a scene's parameters.
    pub fn build(p: &Props) -> Result<Point, Invalid> {
        let position = required(p, p.numbers::<3>("position")?, "position", "point light")?;
        let position = finite3_value(p, "position", position)?;
        required(p, p.numbers::<3>("intensity")?, "intensity", "point light")?;
        let intensity = nonneg3(p, "intensity", [0.0; 3])?;
        Ok(Point {
            position,
            intensity,
        })
    }

    /// The shadow ray's target and the irradiance weight `I / r²` at `p`.
    /// The power it emits, `4π · I` (mean over the colour channels).
    pub fn power(&self) -> f32 {
        4.0 * std::f32::consts::PI * mean(self.intensity)
    }

    /// What a light BVH knows of it: a point emitting in every direction.
    pub fn bounds(&self) -> LightBounds {
        let at = Aabb::new(self.position, self.position);
        LightBounds::new(at, Vec3::Z, self.power(), -1.0, 0.0)
    }

    #[inline]
    pub(super) fn sample(&self, p: Vec3) -> Option<LightSample> {
        let to = self.position - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        Some(LightSample {
            target: self.position,
            dir: to.normalize_or_zero(),
            weight: self.intensity / r2,
            pdf: 0.0,
        })
    }
}

impl EmitterPlugin for Point {
    type Built = Point;

    fn build(p: &Props, _textures: &Textures) -> Result<Point, Invalid> {
        Point::build(p)
    }
}

impl EmitterModel for Point {
    #[inline]
    fn is_delta(&self) -> bool {
        true
    }

    fn power(&self, _radius: f32) -> f32 {
        Point::power(self)
    }

    fn bounds(&self) -> Option<LightBounds> {
        Some(Point::bounds(self))
    }

    #[inline]
    fn sample_one(&self, r: Reference, _point: Vec3, _d: Distribution) -> Option<LightSample> {
        let p = r.p;
        Point::sample(self, p)
    }

    /// A ray in a direction uniform over the sphere: `I · 4π`.
    fn sample_ray(&self, _: Vec2, u_dir: Vec2, _: f32, _: (Vec3, f32)) -> Option<EmittedRay> {
        Some(EmittedRay {
            origin: self.position,
            dir: square_to_uniform_sphere(u_dir),
            weight: self.intensity * (4.0 * std::f32::consts::PI),
            normal: None,
        })
    }
}
