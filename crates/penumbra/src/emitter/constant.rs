//! `constant`: radiance arriving from every direction at infinity — the
//! scene's background (`render.background`), what rays that hit nothing
//! see (Mitsuba 3's `constant` emitter).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radiance` | colour ≥ 0 | **required** | the radiance of every direction |
//!
//! Sampled, as Mitsuba samples it, uniformly over the sphere of directions.

use crate::texture::Textures;

use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{ray_from_infinity, EmittedRay};
use crate::description::check::{nonneg3, required};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::warp::{square_to_uniform_sphere, square_to_uniform_sphere_pdf};

#[derive(Clone, Copy, Debug)]
pub struct Constant {
    pub radiance: Rgb,
}

impl Constant {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "constant",
        what: "constant emitter",
        doc: "the background: the same radiance from every direction, at infinity",
        mitsuba: &["constant"],
        params: &[Param::new(
            "radiance",
            Type::Colour,
            "required",
            "the radiance of every direction, ≥ 0",
        )
        .range(Range::NonNegative)],
    };

    /// How Mitsuba's `constant` maps onto it.
    pub const MITSUBA: Mitsuba =
        Mitsuba::differs("`render.background`: one per scene; `whitted` does not light by it");

    /// The emitter of a scene's parameters.
    pub fn build(p: &Props) -> Result<Constant, Invalid> {
        required(
            p,
            p.numbers::<3>("radiance")?,
            "radiance",
            "constant emitter",
        )?;
        Ok(Constant {
            radiance: nonneg3(p, "radiance", [0.0; 3])?,
        })
    }

    /// The direction toward the background for the point `u` of the unit
    /// square, and its solid-angle density.
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let dir = square_to_uniform_sphere(u);
        (dir, square_to_uniform_sphere_pdf(dir))
    }

    /// The power it brings into a scene of bounding radius `radius`: the
    /// radiance of the whole sphere of directions through the disk of that
    /// radius, `4π · π r² L` (mean over the colour channels), as pbrt-v4
    /// counts a light at infinity.
    pub fn power(&self, radius: f32) -> f32 {
        let pi = std::f32::consts::PI;
        4.0 * pi * pi * radius * radius * super::bounds::mean(self.radiance)
    }

    /// The density of [`sample`](Self::sample) for any direction.
    pub fn pdf(&self) -> f32 {
        square_to_uniform_sphere_pdf(Vec3::Z)
    }
}

impl EmitterPlugin for Constant {
    type Built = Constant;

    fn build(p: &Props, _textures: &Textures) -> Result<Constant, Invalid> {
        Constant::build(p)
    }
}

impl EmitterModel for Constant {
    #[inline]
    fn is_infinite(&self) -> bool {
        true
    }

    fn power(&self, radius: f32) -> f32 {
        Constant::power(self, radius)
    }

    #[inline]
    fn eval_miss(&self, _dir: Vec3) -> Rgb {
        self.radiance
    }

    fn sample_direction(&self, u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        let (dir, pdf) = Constant::sample(self, u);
        Some((dir, self.radiance, pdf))
    }

    fn pdf_direction(&self, _dir: Vec3) -> f32 {
        Constant::pdf(self)
    }

    /// A ray from infinity: its direction drawn as
    /// [`sample_direction`](EmitterModel::sample_direction) draws it, its
    /// origin on the disk of the scene's bounding sphere facing it.
    fn sample_ray(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        _: f32,
        sphere: (Vec3, f32),
    ) -> Option<EmittedRay> {
        let (to, l, pdf) = self.sample_direction(u_dir)?;
        ray_from_infinity(to, l, pdf, u_pos, sphere)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Directions cover the sphere evenly (each octant an eighth) at the
    /// density `1 / 4π` that weighs them.
    #[test]
    fn directions_are_uniform_over_the_sphere() {
        let c = Constant { radiance: Rgb::ONE };
        let mut rng = Rng::new(3);
        let mut octants = [0u32; 8];
        let n = 80_000;
        for _ in 0..n {
            let (d, pdf) = c.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!((d.length() - 1.0).abs() < 1e-5);
            assert!((pdf * 4.0 * std::f32::consts::PI - 1.0).abs() < 1e-6);
            let k =
                usize::from(d.x > 0.0) | usize::from(d.y > 0.0) << 1 | usize::from(d.z > 0.0) << 2;
            octants[k] += 1;
        }
        for o in octants {
            assert!(
                (f64::from(o) / f64::from(n) - 0.125).abs() < 0.005,
                "{octants:?}"
            );
        }
    }
}
