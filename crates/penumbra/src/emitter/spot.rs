//! `spot`: a point light shining a cone (Mitsuba 3's `spot`). Its
//! intensity is `intensity` along the axis, constant out to `beam_width`
//! from it, falls linearly with the angle to 0 at `cutoff_angle`, and is 0
//! beyond: with θ the angle to the axis,
//!
//! `I(θ) = intensity · clamp((cutoff_angle − θ) / (cutoff_angle − beam_width), 0, 1)`.
//!
//! Like `point` it has no surface: its one shadow ray goes to its position.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `position` | vector | [0, 0, 0] | where it is |
//! | `look_at` | vector | `position` + [0, 0, 1] | a point on its axis, which it shines toward |
//! | `intensity` | colour ≥ 0 | [1, 1, 1] | radiant intensity (W/sr per channel) along the axis |
//! | `cutoff_angle` | number in (0, 180) | 20 | degrees from the axis where the light ends |
//! | `beam_width` | number in [0, `cutoff_angle`] | `cutoff_angle` · 3/4 | degrees from the axis of full intensity |
//! | `texture` | colour ≥ 0 or texture | none | a picture projected through the cone, multiplying `intensity` |
//! | `up` | vector | [0, 1, 0] | the light's local `+y`, which orients `texture` |
//!
//! `texture` is projected as Mitsuba projects it: in the light's own frame
//! (`x`, `y` across the axis, `z` along it; `y` is `up` made orthogonal to
//! the axis, `x = y × z`), the direction `(x, y, z)` toward a point looks up
//! `(u, v) = (½ + ½ x / (z tan c), ½ + ½ y / (z tan c))`, `c` the cutoff
//! angle: the square `[0, 1]²` spans the square around the cone's disc.
//!
//! Mitsuba's `to_world` places the light at its origin shining along its
//! `+z`: the XML reader gives it as `position`, `look_at` and `up` (the
//! images of the origin, of `+z` and of the direction `+y`).

use crate::texture::Textures;

use super::bounds::{mean, LightBounds};
use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{EmittedRay, LightSample, Reference};
use crate::description::check::{finite3, nonneg3, range};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::Frame;
use crate::math::{Aabb, Rgb, Vec2, Vec3};
use crate::sampling::warp::square_to_uniform_cone;
use crate::sampling::Distribution;
use crate::texture::Texture;

#[derive(Clone, Debug)]
pub struct Spot {
    pub position: Vec3,
    /// Unit direction of the axis.
    pub axis: Vec3,
    pub intensity: Rgb,
    /// The picture projected through the cone, and the light's local
    /// `x` and `y` (unit, across the axis) that orient it.
    projected: Option<(Texture, Vec3, Vec3)>,
    /// tan(cutoff): the half side of the picture at distance 1 on the axis.
    tan_cutoff: f32,
    cos_cutoff: f32,
    cos_beam: f32,
    cutoff: f32,
    /// 1 / (cutoff − beam width), in radians; infinite for a hard edge.
    inv_transition: f32,
}

impl Spot {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "spot",
        what: "spot light",
        doc: "a point emitting in a cone, falling off linearly in angle toward its edge",
        mitsuba: &["spot"],
        params: &[
            Param::new("position", Type::Vector, "[0, 0, 0]", "where it is").penumbra_only(),
            Param::new(
                "look_at",
                Type::Vector,
                "`position` + [0, 0, 1]",
                "a point on its axis, which it shines toward",
            )
            .penumbra_only(),
            Param::new(
                "intensity",
                Type::Colour,
                "[1, 1, 1]",
                "radiant intensity (W/sr per channel) along the axis, ≥ 0",
            )
            .range(Range::NonNegative),
            Param::new(
                "cutoff_angle",
                Type::Number,
                "20",
                "degrees from the axis where the light ends, in (0, 180)",
            ),
            Param::new(
                "beam_width",
                Type::Number,
                "`cutoff_angle` · 3/4",
                "degrees from the axis of full intensity, in [0, `cutoff_angle`]",
            ),
            Param::new(
                "texture",
                Type::ColourTexture,
                "none",
                "a picture projected through the cone, multiplying `intensity`, each channel ≥ 0",
            )
            .range(Range::NonNegative),
            Param::new(
                "up",
                Type::Vector,
                "[0, 1, 0]",
                "the light's local +y (made orthogonal to the axis), which orients `texture`",
            )
            .penumbra_only(),
        ],
    };

    /// How Mitsuba's `spot` maps onto it.
    pub const MITSUBA: Mitsuba = Mitsuba {
        differences:
            "a `texture` that does not vary (a plain value) is taken, where Mitsuba refuses it",
        reads: &["to_world"],
        adapt: Some(Adapt::Node(adapt::spot)),
    };

    /// The light of a scene's parameters.
    pub fn build(p: &Props, textures: &Textures) -> Result<Spot, Invalid> {
        let position = finite3(p, "position", [0.0; 3])?;
        let look_at = finite3(p, "look_at", (position + Vec3::Z).to_array())?;
        let axis = look_at - position;
        if axis.length_squared() <= 0.0 {
            return Err(p.error("look_at", "must differ from `position`"));
        }
        let intensity = nonneg3(p, "intensity", [1.0; 3])?;
        let cutoff = range(p, "cutoff_angle", 20.0, 0.0, 180.0)?;
        if cutoff <= 0.0 || cutoff >= 180.0 {
            return Err(p.error(
                "cutoff_angle",
                format!("must be strictly between 0 and 180 degrees, got {cutoff}"),
            ));
        }
        let beam = range(p, "beam_width", cutoff * 0.75, 0.0, cutoff)?;
        let up = finite3(p, "up", [0.0, 1.0, 0.0])?;
        let spot = Spot::new(position, axis, intensity, cutoff, beam);
        if !p.has("texture") {
            return Ok(spot);
        }
        let texture = textures.colour(p, "texture", Rgb::ONE)?;
        if let Texture::MeshAttribute(_) = texture {
            return Err(p.error(
                "texture",
                "a `mesh_attribute` has no mesh to read on a light",
            ));
        }
        if texture.bounds().0.min_element() < 0.0 {
            return Err(p.error("texture", "must not be negative"));
        }
        let y = up - spot.axis * up.dot(spot.axis);
        if y.length_squared() <= 1e-12 * up.length_squared() || !y.is_finite() {
            return Err(p.error("up", "must not be along the axis (nor zero)"));
        }
        Ok(spot.projecting(texture, y))
    }

    /// The spot projecting `texture` through its cone, `up` (across the
    /// axis, any length > 0) its local `+y`.
    pub fn projecting(mut self, texture: Texture, up: Vec3) -> Spot {
        let y = (up - self.axis * up.dot(self.axis)).normalize();
        let x = y.cross(self.axis);
        self.projected = Some((texture, x, y));
        self
    }

    /// Mitsuba's coordinates of the picture along the unit direction `d`
    /// from the light (in the cone): the local direction's `x / z` and
    /// `y / z` over tan(cutoff), from −1 to 1, shifted to [0, 1].
    #[inline]
    pub fn uv(&self, d: Vec3, x: Vec3, y: Vec3) -> Vec2 {
        let z = d.dot(self.axis) * self.tan_cutoff;
        Vec2::new(0.5 + 0.5 * d.dot(x) / z, 0.5 + 0.5 * d.dot(y) / z)
    }

    /// A spot light at `position` shining along `axis` (any length > 0),
    /// angles in degrees.
    pub fn new(position: Vec3, axis: Vec3, intensity: Rgb, cutoff: f32, beam: f32) -> Spot {
        let (cutoff, beam) = (cutoff.to_radians(), beam.to_radians());
        Spot {
            position,
            axis: axis.normalize(),
            intensity,
            projected: None,
            tan_cutoff: cutoff.tan(),
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
            cutoff,
            inv_transition: 1.0 / (cutoff - beam),
        }
    }

    /// The share of `intensity` sent along the unit direction `d`.
    #[inline]
    pub fn falloff(&self, d: Vec3) -> f32 {
        let c = self.axis.dot(d);
        if c <= self.cos_cutoff {
            0.0
        } else if c >= self.cos_beam {
            1.0
        } else {
            ((self.cutoff - c.clamp(-1.0, 1.0).acos()) * self.inv_transition).clamp(0.0, 1.0)
        }
    }

    /// The shadow ray's target and the irradiance weight `I(θ) / r²` at
    /// `p`; `None` outside the cone.
    /// The power it emits, `2π ∫ I · falloff(θ) sin θ dθ` (mean over the
    /// colour channels): full intensity out to the beam angle β, then
    /// falling linearly in angle to the cutoff c, which integrates to
    /// `2π I (1 − (sin c − sin β) / (c − β))` (`2π I (1 − cos c)` when
    /// β = c).
    pub fn power(&self) -> f32 {
        let beam = self.cos_beam.clamp(-1.0, 1.0).acos();
        let c = self.cutoff;
        let solid = if c - beam > 1e-6 {
            1.0 - (c.sin() - beam.sin()) / (c - beam)
        } else {
            1.0 - c.cos()
        };
        2.0 * std::f32::consts::PI * solid * mean(self.intensity)
    }

    /// What a light BVH knows of it: a point whose cone of full intensity
    /// (the beam angle) is widened by the falloff out to the cutoff.
    pub fn bounds(&self) -> LightBounds {
        let at = Aabb::new(self.position, self.position);
        let beam = self.cos_beam.clamp(-1.0, 1.0).acos();
        let cos_e = (self.cutoff - beam).max(0.0).cos();
        LightBounds::new(at, self.axis, self.power(), self.cos_beam, cos_e)
    }

    #[inline]
    pub(super) fn sample(&self, p: Vec3) -> Option<LightSample> {
        let to = self.position - p;
        let r2 = to.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        let dir = to.normalize_or_zero();
        let falloff = self.falloff(-dir);
        if falloff <= 0.0 {
            return None;
        }
        let intensity = match &self.projected {
            None => self.intensity,
            Some((t, x, y)) => self.intensity * t.eval_uv(self.uv(-dir, *x, *y)),
        };
        Some(LightSample {
            target: self.position,
            dir,
            weight: intensity * (falloff / r2),
            pdf: 0.0,
        })
    }
}

impl EmitterPlugin for Spot {
    type Built = Spot;

    fn build(p: &Props, textures: &Textures) -> Result<Spot, Invalid> {
        Spot::build(p, textures)
    }
}

impl EmitterModel for Spot {
    #[inline]
    fn is_delta(&self) -> bool {
        true
    }

    fn power(&self, _radius: f32) -> f32 {
        Spot::power(self)
    }

    fn bounds(&self) -> Option<LightBounds> {
        Some(Spot::bounds(self))
    }

    #[inline]
    fn sample_one(&self, r: Reference, _point: Vec3, _d: Distribution) -> Option<LightSample> {
        let p = r.p;
        Spot::sample(self, p)
    }

    /// A ray in a direction uniform over the cutoff's cone (as Mitsuba
    /// draws it): the intensity along it, times its falloff and picture,
    /// over the cone's density.
    fn sample_ray(&self, _: Vec2, u_dir: Vec2, _: f32, _: (Vec3, f32)) -> Option<EmittedRay> {
        let dir = Frame::from_normal(self.axis)
            .to_world(square_to_uniform_cone(u_dir, self.cos_cutoff))
            .normalize();
        let falloff = self.falloff(dir);
        if falloff <= 0.0 {
            return None;
        }
        let intensity = match &self.projected {
            None => self.intensity,
            Some((t, x, y)) => self.intensity * t.eval_uv(self.uv(dir, *x, *y)),
        };
        let solid = 2.0 * std::f32::consts::PI * (1.0 - self.cos_cutoff);
        Some(EmittedRay {
            origin: self.position,
            dir,
            weight: intensity * (falloff * solid),
            normal: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The profile against the formula written with the angle: full to the
    /// beam width, 0 past the cutoff, linear in between, for hard and soft
    /// edges and a wide cone.
    #[test]
    fn falloff_follows_mitsubas_profile() {
        for (cutoff, beam) in [(20.0f32, 15.0f32), (30.0, 0.0), (10.0, 10.0), (120.0, 45.0)] {
            let s = Spot::new(
                Vec3::ZERO,
                Vec3::new(0.0, -2.0, 0.0),
                Rgb::ONE,
                cutoff,
                beam,
            );
            for k in 0..=400 {
                let theta = (k as f32 * 0.5).to_radians() * cutoff / 150.0 * 1.5;
                let d = Vec3::new(theta.sin(), -theta.cos(), 0.0);
                let deg = theta.to_degrees();
                let want = if deg >= cutoff {
                    0.0
                } else if deg <= beam {
                    1.0
                } else {
                    (cutoff - deg) / (cutoff - beam)
                };
                let got = s.falloff(d);
                assert!(
                    (got - want).abs() < 2e-3,
                    "cutoff {cutoff}, beam {beam}, θ {deg}: {got} vs {want}"
                );
            }
        }
    }

    /// The irradiance on a plane 2 below a spot pointing down is
    /// `I(θ) cos θ / r²`; its integral over the plane is the power
    /// `2π ∫ I(θ) sin θ dθ` (by quadrature over θ), here summed over a grid.
    #[test]
    fn irradiance_on_a_plane_matches_the_power() {
        let h = 2.0f32;
        let s = Spot::new(
            Vec3::new(0.0, h, 0.0),
            -Vec3::Y,
            Rgb::splat(3.0),
            30.0,
            20.0,
        );
        // On the axis: I / h².
        let at = s.sample(Vec3::ZERO).unwrap();
        assert!((at.weight.r - 3.0 / (h * h)).abs() < 1e-6);
        assert!(
            s.sample(Vec3::new(5.0, 0.0, 0.0)).is_none(),
            "outside the cone"
        );
        let (n, half) = (600, 1.5f32);
        let cell = (2.0 * half / n as f32).powi(2);
        let mut on_plane = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let x = -half + (i as f32 + 0.5) * 2.0 * half / n as f32;
                let z = -half + (j as f32 + 0.5) * 2.0 * half / n as f32;
                if let Some(ls) = s.sample(Vec3::new(x, 0.0, z)) {
                    on_plane += f64::from(ls.weight.r * ls.dir.y * cell);
                }
            }
        }
        let steps = 100_000;
        let mut power = 0.0f64;
        for k in 0..steps {
            let t = (k as f64 + 0.5) / steps as f64 * std::f64::consts::PI;
            let d = Vec3::new(t.sin() as f32, -(t.cos() as f32), 0.0);
            power += f64::from(3.0 * s.falloff(d)) * t.sin() * std::f64::consts::PI / steps as f64;
        }
        power *= 2.0 * std::f64::consts::PI;
        assert!(
            (f64::from(s.power()) / power - 1.0).abs() < 1e-3,
            "power {} against {power}",
            s.power()
        );
        assert!(
            (on_plane / power - 1.0).abs() < 2e-3,
            "{on_plane} on the plane, {power} emitted"
        );
        // A random point: the same weight as computed by hand.
        let mut rng = Rng::new(5);
        for _ in 0..100 {
            let p = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let to = s.position - p;
            let want = 3.0 * s.falloff(-to.normalize()) / to.length_squared();
            let got = s.sample(p).map_or(0.0, |l| l.weight.g);
            assert!((got - want).abs() <= 1e-5 * want.max(1.0));
        }
    }

    /// A spot projecting a constant texture of 1 gives, bit for bit, the
    /// weights of the spot without one.
    #[test]
    fn a_texture_of_one_changes_nothing() {
        let plain = Spot::new(
            Vec3::new(0.2, 1.5, -0.3),
            Vec3::new(0.1, -1.0, 0.2),
            Rgb::new(3.0, 2.0, 0.7),
            35.0,
            20.0,
        );
        let textured = plain
            .clone()
            .projecting(Texture::Constant(Rgb::ONE), Vec3::new(0.0, 0.0, 1.0));
        let mut rng = Rng::new(9);
        let mut lit = 0;
        for _ in 0..500 {
            let p = Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-1.0, 0.5),
                rng.range(-2.0, 2.0),
            );
            let (a, b) = (plain.sample(p), textured.sample(p));
            assert_eq!(a.is_some(), b.is_some());
            if let (Some(a), Some(b)) = (a, b) {
                let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                assert_eq!(bits(a.weight), bits(b.weight));
                assert_eq!(a.dir, b.dir);
                lit += 1;
            }
        }
        assert!(lit > 50, "{lit} points lit");
    }

    /// The picture's orientation, by Mitsuba's formula written out: in the
    /// light's frame (x, y across the axis, z along it) the direction
    /// (x, y, z) reads (u, v) = (½ + ½ x / (z tan c), ½ + ½ y / (z tan c)),
    /// texel column ⌊2u⌋ and row ⌊2v⌋ of a 2 × 2 picture (row 0 on top).
    /// The spot shines down −y with its local +y along world +z, so its
    /// local +x is y × z = (+z) × (−y) = +x.
    #[test]
    fn the_picture_is_oriented_as_mitsubas() {
        use std::sync::Arc;

        use crate::input::image::Image;
        use crate::texture::bitmap::{Bitmap, Filter, Wrap};
        use crate::texture::UvTransform;

        // Texel (column, row): red (0, 0), green (1, 0), blue (0, 1), grey (1, 1).
        let texels = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.5],
        ];
        let image = Image {
            width: 2,
            height: 2,
            channels: 3,
            pixels: texels.iter().flatten().copied().collect(),
        };
        let picture = Texture::Bitmap(Bitmap::new(
            Arc::new(image),
            Filter::Nearest,
            Wrap::Clamp,
            UvTransform::IDENTITY,
        ));
        let cutoff = 30.0f32;
        let spot =
            Spot::new(Vec3::ZERO, -Vec3::Y, Rgb::ONE, cutoff, cutoff).projecting(picture, Vec3::Z);
        let tan = cutoff.to_radians().tan();
        // (point, its texel): x > 0 is column 1, z > 0 (local +y) row 1.
        for (x, z, texel) in [
            (-0.2, -0.2, 0),
            (0.2, -0.2, 1),
            (-0.2, 0.2, 2),
            (0.2, 0.2, 3),
        ] {
            let p = Vec3::new(x, -1.0, z);
            let ls = spot.sample(p).expect("in the cone");
            let r2 = p.length_squared();
            // Local (x, y, z) of the direction from the light = (x, z, 1).
            let (u, v) = (0.5 + 0.5 * x / tan, 0.5 + 0.5 * z / tan);
            let want = texels[(v * 2.0).floor() as usize * 2 + (u * 2.0).floor() as usize];
            assert_eq!(want, texels[texel]);
            let got = ls.weight * r2;
            assert!(
                (got - Rgb::from_array(want)).abs().max_element() < 1e-5,
                "({x}, {z}): {got:?}"
            );
            let uv = spot.uv(p.normalize(), Vec3::X, Vec3::Z);
            assert!((uv - Vec2::new(u, v)).length() < 1e-6, "{uv:?}");
        }
        // The picture's edge is the cone's: a point on the cutoff's circle
        // along local +x reads u = 1.
        let edge = Vec3::new(tan, -1.0, 0.0).normalize();
        assert!((spot.uv(edge, Vec3::X, Vec3::Z).x - 1.0).abs() < 1e-5);
    }
}
