//! `projector`: a point light projecting an image, the reciprocal of a
//! pinhole camera (Mitsuba 3's `projector`).
//!
//! The light sits at `position`, looks toward `look_at` with `up` above,
//! and casts `irradiance` (a colour or a texture) through a pinhole onto
//! its image plane at distance 1, whose width the horizontal field of view
//! sets: a point at `(x, y, z)` in the light's frame (`z` forward, `x` to
//! the image's left) receives texel
//!
//! `u = 1/2 − x / (2 z tan(fov_x/2))`, `v = 1/2 − a · y / (2 z tan(fov_x/2))`
//!
//! (`a` the texture's aspect, width over height; 1 for a colour), nothing
//! outside `[0, 1]²` or behind the light. Its radiance toward that point
//! carries the inverse of a pinhole camera's sensitivity, `π / cos³θ`, so
//! that a constant irradiance lands on a plane facing it as a constant:
//! the irradiance `E` arriving at distance `d` and angle `θ` is
//! `E = scale · π · T(u, v) / (d² cos³θ)` times the receiver's cosine.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `position` | vector | [0, 0, 0] | the pinhole |
//! | `look_at` | vector | `position` + [0, 0, 1] | a point on its axis |
//! | `up` | vector | [0, 1, 0] | the image's up |
//! | `irradiance` | colour or texture | [1, 1, 1] | the image on the plane at distance 1 |
//! | `scale` | number ≥ 0 | 1 | a factor on `irradiance` |
//! | `fov` | number in (0, 180) | from `focal_length` | field of view in degrees along `fov_axis` |
//! | `fov_axis` | `x`, `y`, `diagonal`, `smaller`, `larger` | `x` | the axis `fov` spans |
//! | `focal_length` | string | `50mm` | 35 mm film equivalent focal length (a diagonal field of view), without `fov` |

use std::f32::consts::PI;

use super::bounds::{mean, LightBounds};
use super::model::{EmitterModel, EmitterPlugin};
use super::sample::{EmittedRay, LightSample, Reference};
use crate::description::check::{finite3, range};
use crate::description::mitsuba::adapt;
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Aabb, Rgb, Vec2, Vec3};
use crate::sampling::Distribution;
use crate::texture::{Texture, Textures};

/// The axes a field of view may span.
const FOV_AXES: [&str; 5] = ["x", "y", "diagonal", "smaller", "larger"];

#[derive(Clone, Debug)]
pub struct Projector {
    pub position: Vec3,
    /// The light's frame: the image's left, up and the axis (unit).
    left: Vec3,
    up: Vec3,
    axis: Vec3,
    pub irradiance: Texture,
    pub scale: f32,
    /// `1 / tan(fov_x / 2)`.
    cot: f32,
    /// The texture's width over its height.
    aspect: f32,
}

impl Projector {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "projector",
        what: "projector",
        doc: "a point light projecting an image through a pinhole",
        mitsuba: &["projector"],
        params: &[
            Param::new("position", Type::Vector, "[0, 0, 0]", "the pinhole").penumbra_only(),
            Param::new(
                "look_at",
                Type::Vector,
                "`position` + [0, 0, 1]",
                "a point on its axis",
            )
            .penumbra_only(),
            Param::new("up", Type::Vector, "[0, 1, 0]", "the image's up").penumbra_only(),
            Param::new(
                "irradiance",
                Type::ColourTexture,
                "[1, 1, 1]",
                "the image on the plane at distance 1 (a colour or a texture), ≥ 0",
            )
            .range(Range::NonNegative),
            Param::new("scale", Type::Number, "1", "a factor on `irradiance`, ≥ 0"),
            Param::new(
                "fov",
                Type::Number,
                "from `focal_length`",
                "field of view in degrees along `fov_axis`, in (0, 180)",
            ),
            Param::new(
                "fov_axis",
                Type::Choice("field of view axis", &FOV_AXES),
                "x",
                "the axis `fov` spans (smaller and larger: of the texture's sides)",
            ),
            Param::new(
                "focal_length",
                Type::String,
                "50mm",
                "35 mm film equivalent focal length, such as `35mm` (a diagonal field of view), \
                 when `fov` is not given",
            ),
        ],
    };

    /// How Mitsuba's `projector` maps onto it.
    pub const MITSUBA: Mitsuba = Mitsuba {
        differences: "`to_world` must be a rotation and a translation (a `lookat`): one that \
            scales or shears is refused",
        reads: &["to_world"],
        adapt: Some(Adapt::Node(adapt::projector)),
    };

    /// The light of a scene's parameters, among the scene's `textures`.
    pub fn build(p: &Props, textures: &Textures) -> Result<Projector, Invalid> {
        let position = finite3(p, "position", [0.0; 3])?;
        let look_at = finite3(p, "look_at", (position + Vec3::Z).to_array())?;
        let up = finite3(p, "up", [0.0, 1.0, 0.0])?;
        let axis = (look_at - position).normalize_or_zero();
        if axis == Vec3::ZERO {
            return Err(p.error("look_at", "must differ from `position`"));
        }
        let left = up.cross(axis).normalize_or_zero();
        if left == Vec3::ZERO || !left.is_finite() {
            return Err(p.error(
                "up",
                "must not be along the axis from `position` to `look_at`",
            ));
        }
        let irradiance = textures.colour(p, "irradiance", Rgb::ONE)?;
        let scale = range(p, "scale", 1.0, 0.0, f32::MAX)?;
        let (w, h) = match &irradiance {
            Texture::Bitmap(b) => (b.image.width, b.image.height),
            _ => (1, 1),
        };
        let aspect = w as f64 / h as f64;
        let fov = fov_x(p, aspect)?;
        Ok(Projector {
            position,
            left,
            up: axis.cross(left),
            axis,
            irradiance,
            scale,
            cot: (1.0 / (0.5 * fov.to_radians()).tan()) as f32,
            aspect: aspect as f32,
        })
    }

    /// The power it sends: the irradiance's mean over the image at
    /// distance 1 (a `2/cot × 2/(a·cot)` rectangle) times its area, times π.
    pub fn power(&self) -> f32 {
        let (lo, hi) = self.irradiance.bounds();
        let area = 4.0 / (self.cot * self.cot * self.aspect);
        PI * self.scale * 0.5 * (mean(lo) + mean(hi)) * area
    }

    /// The point's place on the image, and its depth along the axis;
    /// `None` behind the light or off the image.
    fn project(&self, p: Vec3) -> Option<(Vec2, f32)> {
        let d = p - self.position;
        let z = d.dot(self.axis);
        if z <= 0.0 {
            return None;
        }
        let (x, y) = (d.dot(self.left), d.dot(self.up));
        let u = 0.5 - 0.5 * self.cot * x / z;
        let v = 0.5 - 0.5 * self.aspect * self.cot * y / z;
        ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some((Vec2::new(u, v), z))
    }

    #[inline]
    pub(super) fn sample(&self, p: Vec3) -> Option<LightSample> {
        let (uv, z) = self.project(p)?;
        let to = self.position - p;
        let dist = to.length();
        if dist <= 0.0 {
            return None;
        }
        let dir = to / dist;
        // cos θ at the light: the axis against the direction to the point.
        let cos = -self.axis.dot(dir);
        let e = self.irradiance.eval_uv(uv) * (PI * self.scale / (z * z * cos));
        Some(LightSample {
            target: self.position,
            dir,
            weight: e,
            pdf: 0.0,
        })
    }
}

/// The horizontal field of view in degrees, from `fov` along `fov_axis`
/// or from `focal_length`, for an image of `aspect` (as Mitsuba's
/// `parse_fov`).
fn fov_x(p: &Props, aspect: f64) -> Result<f64, Invalid> {
    let fov = p.f32("fov")?;
    let focal = p.string("focal_length")?;
    let (fov, axis) = match (fov, focal) {
        (Some(_), Some(_)) => {
            return Err(p.error(
                "focal_length",
                "give a field of view (`fov`) or a focal length, not both",
            ))
        }
        (Some(f), None) => {
            if !(f > 0.0 && f < 180.0) {
                return Err(p.error(
                    "fov",
                    format!("must be strictly between 0 and 180 degrees, got {f}"),
                ));
            }
            let axis = p
                .choice("fov_axis", "field of view axis", &FOV_AXES)?
                .unwrap_or("x");
            let axis = match axis {
                "smaller" if aspect > 1.0 => "y",
                "smaller" => "x",
                "larger" if aspect > 1.0 => "x",
                "larger" => "y",
                a => a,
            };
            (f64::from(f), axis)
        }
        (None, focal) => {
            let text = focal.unwrap_or("50mm");
            let mm = text.strip_suffix("mm").unwrap_or(text);
            let f: f64 = mm
                .trim()
                .parse()
                .ok()
                .filter(|f: &f64| *f > 0.0 && f.is_finite())
                .ok_or_else(|| {
                    p.error(
                        "focal_length",
                        format!(
                            "must be a positive length in millimetres such as `50mm`, got `{text}`"
                        ),
                    )
                })?;
            let diagonal = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
            (2.0 * (diagonal / (2.0 * f)).atan().to_degrees(), "diagonal")
        }
    };
    let half = (0.5 * fov).to_radians().tan();
    Ok(match axis {
        "y" => 2.0 * (half * aspect).atan().to_degrees(),
        "diagonal" => {
            let width = 2.0 * half / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            2.0 * (0.5 * width).atan().to_degrees()
        }
        _ => fov,
    })
}

impl EmitterPlugin for Projector {
    type Built = Projector;

    fn build(p: &Props, textures: &Textures) -> Result<Projector, Invalid> {
        Projector::build(p, textures)
    }
}

impl EmitterModel for Projector {
    #[inline]
    fn is_delta(&self) -> bool {
        true
    }

    fn power(&self, _radius: f32) -> f32 {
        Projector::power(self)
    }

    fn bounds(&self) -> Option<LightBounds> {
        let at = Aabb::new(self.position, self.position);
        // The cone around the axis holding the image's corners.
        let corner = (1.0 + self.aspect * self.aspect).sqrt() / (self.cot * self.aspect);
        let cos = 1.0 / (1.0 + corner * corner).sqrt();
        Some(LightBounds::new(
            at,
            self.axis,
            Projector::power(self),
            cos,
            0.0,
        ))
    }

    #[inline]
    fn sample_one(&self, r: Reference, _point: Vec3, _d: Distribution) -> Option<LightSample> {
        Projector::sample(self, r.p)
    }

    /// A ray through a point uniform over the image (at distance 1 on the
    /// axis, a rectangle of area `4 / (cot² · aspect)`): the irradiance
    /// there, times `π · scale` and that area (the intensity `E π s / cos³`
    /// over the direction's density `cos³ / area`).
    fn sample_ray(&self, _: Vec2, u_dir: Vec2, _: f32, _: (Vec3, f32)) -> Option<EmittedRay> {
        let (u, v) = (u_dir.x, u_dir.y);
        let x = (1.0 - 2.0 * u) / self.cot;
        let y = (1.0 - 2.0 * v) / (self.aspect * self.cot);
        let dir = (self.axis + x * self.left + y * self.up).normalize();
        let area = 4.0 / (self.cot * self.cot * self.aspect);
        Some(EmittedRay {
            origin: self.position,
            dir,
            weight: self.irradiance.eval_uv(Vec2::new(u, v)) * (PI * self.scale * area),
            normal: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::from_toml;
    use std::path::Path;

    /// `f` of the parameters of a projector of `text` (TOML keys).
    fn with_props<T>(text: &str, f: impl FnOnce(&Props) -> T) -> T {
        let root = from_toml(
            &format!("[[lights]]\ntype = \"projector\"\n{text}\n"),
            Path::new("t.toml"),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let node = root.child(Kind::Emitter).expect("a light");
        f(&Props::new(node))
    }

    fn projector(text: &str) -> Result<Projector, Invalid> {
        with_props(text, |p| {
            Projector::build(p, &Textures::new(Path::new(".")))
        })
    }

    /// A constant image lands on a plane facing the light as a constant
    /// irradiance: the `π / cos³θ` cancels the inverse square law and both
    /// cosines, so every lit point of the plane z = −1 (the light at the
    /// origin looking down −z) receives `π · scale · T · cosθ_receiver /
    /// (d² cos³θ)` = `π · scale · T`.
    #[test]
    fn a_constant_image_lights_a_facing_plane_evenly() {
        let p = projector("look_at = [0, 0, -1]\nirradiance = [0.5, 1, 2]\nscale = 3\nfov = 90")
            .unwrap();
        for (x, y) in [(0.0, 0.0), (0.3, -0.2), (0.99, 0.99), (-0.9, 0.5)] {
            let at = Vec3::new(x, y, -1.0);
            let s = p.sample(at).expect("on the image");
            let cos_receiver = s.dir.dot(Vec3::Z);
            let e = s.weight * cos_receiver;
            let want = Rgb::new(0.5, 1.0, 2.0) * (PI * 3.0);
            assert!(
                (e - want).abs().max_element() < 1e-4 * want.max_element(),
                "{x}, {y}: {e:?}"
            );
        }
        // Off the image (fov 90: |x| ≤ z) and behind the light: nothing.
        assert!(p.sample(Vec3::new(1.01, 0.0, -1.0)).is_none());
        assert!(p.sample(Vec3::new(0.0, 0.0, 1.0)).is_none());
    }

    /// The image's orientation: `u` grows to the image's right (away
    /// from `left` = up × axis), `v` downward, as Mitsuba's projection.
    #[test]
    fn the_image_is_placed_as_mitsuba_places_it() {
        let p = projector("look_at = [0, 0, 1]\nfov = 90").unwrap();
        // Looking along +z with +y up, the image's left is +x.
        let (uv, z) = p.project(Vec3::new(0.5, 0.25, 1.0)).unwrap();
        assert_eq!(z, 1.0);
        assert!(
            (uv - Vec2::new(0.25, 0.375)).abs().max_element() < 1e-6,
            "{uv}"
        );
    }

    /// `fov_axis` and `focal_length` give the horizontal field of view
    /// Mitsuba's formulas give.
    #[test]
    fn the_field_of_view_follows_its_axis() {
        let fov = |text: &str, aspect: f64| with_props(text, |p| fov_x(p, aspect).unwrap());
        assert_eq!(fov("fov = 60", 2.0), 60.0);
        let y = fov("fov = 60\nfov_axis = \"y\"", 2.0);
        assert!((y - 2.0 * (30f64.to_radians().tan() * 2.0).atan().to_degrees()).abs() < 1e-9);
        assert_eq!(fov("fov = 60\nfov_axis = \"larger\"", 2.0), 60.0);
        assert_eq!(fov("fov = 60\nfov_axis = \"smaller\"", 2.0), y);
        // 50 mm on a 36 × 24 mm film of aspect 3/2 spans 39.6° across.
        let f = fov("", 1.5);
        assert!((f - 39.597_752_709_049_88).abs() < 1e-6, "{f}");
        assert!(with_props("fov = 30\nfocal_length = \"35mm\"", |p| fov_x(p, 1.0)).is_err());
    }
}
