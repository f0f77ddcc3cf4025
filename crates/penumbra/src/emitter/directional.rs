//! `directional`: light arriving from infinitely far along one direction
//! (Mitsuba 3's `directional`, the sun as a point at infinity). Every
//! point of the scene receives `irradiance` on a surface facing the light;
//! its one shadow ray goes from the shading point against `direction` to
//! beyond the scene's bounding sphere. Rays that hit nothing do not see it.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `direction` | vector ≠ 0 | [0, 0, 1] | the direction the light travels |
//! | `irradiance` | colour ≥ 0 | [1, 1, 1] | irradiance (W/m² per channel) on a surface facing the light |
//!
//! Mitsuba's `to_world` turns `+z` into the direction: the XML reader gives
//! it as `direction`.

use crate::texture::Textures;

use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{EmittedRay, LightSample, Reference};
use crate::description::check::{nonneg3, nonzero3};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_disk_concentric;
use crate::sampling::Distribution;

#[derive(Clone, Copy, Debug)]
pub struct Directional {
    /// Unit direction the light travels.
    pub direction: Vec3,
    pub irradiance: Rgb,
    /// The sphere around the scene that shadow rays leave (see
    /// [`fit`](Self::fit)).
    center: Vec3,
    radius: f32,
}

impl Directional {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "directional",
        what: "directional light",
        doc: "irradiance along one direction from infinity (a sun), seen by no ray",
        mitsuba: &["directional"],
        params: &[
            Param::new(
                "direction",
                Type::Vector,
                "[0, 0, 1]",
                "the direction the light travels, ≠ 0",
            ),
            Param::new(
                "irradiance",
                Type::Colour,
                "[1, 1, 1]",
                "irradiance (W/m² per channel) on a surface facing the light, ≥ 0",
            )
            .range(Range::NonNegative),
        ],
    };

    /// How Mitsuba's `directional` maps onto it.
    pub const MITSUBA: Mitsuba = Mitsuba {
        differences: "",
        reads: &["to_world"],
        adapt: Some(Adapt::Node(adapt::directional)),
    };

    /// The light of a scene's parameters.
    pub fn build(p: &Props) -> Result<Directional, Invalid> {
        let direction = nonzero3(p, "direction", [0.0, 0.0, 1.0])?;
        let irradiance = nonneg3(p, "irradiance", [1.0; 3])?;
        Ok(Directional::new(direction, irradiance))
    }

    /// A light travelling along `direction` (any length > 0), not yet fitted
    /// to a scene.
    pub fn new(direction: Vec3, irradiance: Rgb) -> Directional {
        Directional {
            direction: direction.normalize(),
            irradiance,
            center: Vec3::ZERO,
            radius: 0.0,
        }
    }

    /// Makes shadow rays leave the sphere of `center` and `radius` that
    /// holds the scene.
    pub fn fit(&mut self, center: Vec3, radius: f32) {
        self.center = center;
        self.radius = radius;
    }

    /// The power it brings into a scene of bounding radius `radius`: its
    /// irradiance over the disk of that radius, `π r² E` (mean over the
    /// colour channels), as pbrt-v4 counts a light at infinity.
    pub fn power(&self, radius: f32) -> f32 {
        std::f32::consts::PI * radius * radius * super::bounds::mean(self.irradiance)
    }

    /// The shadow ray toward the light, with a target beyond the scene's
    /// sphere and the irradiance as weight.
    #[inline]
    pub(super) fn sample(&self, p: Vec3) -> Option<LightSample> {
        let dir = -self.direction;
        let far = 2.0 * self.radius.max((p - self.center).length()) + 1.0;
        Some(LightSample {
            target: p + dir * far,
            dir,
            weight: self.irradiance,
            pdf: 0.0,
        })
    }
}

impl EmitterPlugin for Directional {
    type Built = Directional;

    fn build(p: &Props, _textures: &Textures) -> Result<Directional, Invalid> {
        Directional::build(p)
    }
}

impl EmitterModel for Directional {
    #[inline]
    fn is_delta(&self) -> bool {
        true
    }

    fn fit(&mut self, center: Vec3, radius: f32) {
        Directional::fit(self, center, radius);
    }

    fn power(&self, radius: f32) -> f32 {
        Directional::power(self, radius)
    }

    #[inline]
    fn sample_one(&self, r: Reference, _point: Vec3, _d: Distribution) -> Option<LightSample> {
        let p = r.p;
        Directional::sample(self, p)
    }

    /// A ray along the light's direction from a point uniform on the disk
    /// of the scene's bounding sphere facing it: `E · π r²`.
    fn sample_ray(&self, u_pos: Vec2, _: Vec2, _: f32, sphere: (Vec3, f32)) -> Option<EmittedRay> {
        let (center, radius) = sphere;
        if radius <= 0.0 || radius.is_nan() {
            return None;
        }
        let d = square_to_disk_concentric(u_pos) * radius;
        let frame = Frame::from_normal(self.direction);
        let origin = center - self.direction * radius + frame.to_world(Vec3::new(d.x, d.y, 0.0));
        Some(EmittedRay {
            origin,
            dir: self.direction,
            weight: self.irradiance * (std::f32::consts::PI * radius * radius),
            normal: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The irradiance on a plane tilted by θ from the light is `E cos θ`
    /// (weight · cos at the receiver), and the shadow ray leaves the
    /// scene's sphere from any point inside or outside it.
    #[test]
    fn irradiance_on_a_plane_is_e_cos_theta() {
        let mut d = Directional::new(Vec3::new(1.0, -2.0, 0.5), Rgb::new(1.0, 2.0, 3.0));
        d.fit(Vec3::new(1.0, 1.0, 1.0), 3.0);
        for k in 0..=18 {
            let theta = (k as f32 * 5.0).to_radians();
            // A plane whose normal is θ away from the direction toward the light.
            let toward = -d.direction;
            let side = toward.cross(Vec3::X).normalize();
            let n = toward * theta.cos() + side * theta.sin();
            for p in [Vec3::ZERO, Vec3::new(10.0, -4.0, 2.0)] {
                let s = d.sample(p).unwrap();
                let e = s.weight.g * n.dot(s.dir).max(0.0);
                assert!((e - 2.0 * theta.cos()).abs() < 1e-5, "{e}");
                assert!((s.target - d.center).length() > d.radius);
                assert!((s.target - p).normalize().dot(toward) > 0.99999);
            }
        }
    }
}
