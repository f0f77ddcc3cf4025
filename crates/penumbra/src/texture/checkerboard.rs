//! `checkerboard`: two colours alternating in squares of side ½ in
//! `(u, v)` (Mitsuba 3's `checkerboard`). At `(u, v)` mapped by `to_uv`,
//! with `fu`, `fv` the fractional parts: `color0` where `fu > ½` and
//! `fv > ½` agree, `color1` where they differ. The unit square holds four
//! squares, `color0` in its lower-left one.
//!
//! Either colour may be a texture: it is looked up at the surface's own
//! `(u, v)`, not mapped by the checkerboard's `to_uv` (as Mitsuba does).
//!
//! Read as one value (a roughness), the squares swap: `color0` where `fu > ½`
//! and `fv > ½` differ. That is what Mitsuba 3's `eval_1` does, kept so that
//! its scenes render alike.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `color0` | colour ≥ 0 or texture | `[0.4, 0.4, 0.4]` | the colour of the squares where `fu > ½` and `fv > ½` agree |
//! | `color1` | colour ≥ 0 or texture | `[0.2, 0.2, 0.2]` | the colour of the other squares |
//! | `to_uv` | table | identity | a map of `(u, v)` before the lookup (see the [module docs](super)) |

use super::common::{UvTransform, TO_UV};
use super::{Texture, TextureModel, Textures};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::math::{Rgb, Vec2};

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Texture,
    plugin: "checkerboard",
    what: "checkerboard texture",
    doc: "two colours alternating in squares of side ½ in (u, v)",
    mitsuba: &["checkerboard"],
    params: &[
        Param::new(
            "color0",
            Type::ColourTexture,
            "[0.4, 0.4, 0.4]",
            "the colour of the squares where u and v both have fractional parts above ½ or both not, each channel ≥ 0",
        ).range(Range::NonNegative),
        Param::new(
            "color1",
            Type::ColourTexture,
            "[0.2, 0.2, 0.2]",
            "the colour of the other squares, each channel ≥ 0",
        ).range(Range::NonNegative),
        TO_UV,
    ],
};

/// The checkerboard (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard {
    pub color0: Box<Texture>,
    pub color1: Box<Texture>,
    pub to_uv: UvTransform,
}

impl Checkerboard {
    /// Whether `(u, v)` (before `to_uv`) lies in a square of `color0`.
    #[inline]
    fn first(&self, uv: Vec2) -> bool {
        let t = self.to_uv.apply(uv);
        let high = |x: f32| x - x.floor() > 0.5;
        high(t.x) == high(t.y)
    }
}

impl TextureModel for Checkerboard {
    const NAME: &'static str = "checkerboard";
    const SCHEMA: Schema = SCHEMA;

    fn build(p: &Props, textures: &Textures) -> Result<Checkerboard, Invalid> {
        let colour = |name: &str, default: f32| match textures.colour(p, name, Rgb::splat(default))? {
            Texture::MeshAttribute(_) => Err(p.error(
                name,
                "a `mesh_attribute` is read at the point hit, not inside a checkerboard",
            )),
            t => Ok(Box::new(t)),
        };
        Ok(Checkerboard {
            color0: colour("color0", 0.4)?,
            color1: colour("color1", 0.2)?,
            to_uv: UvTransform::read(p)?,
        })
    }

    #[inline]
    fn eval(&self, uv: Vec2) -> Rgb {
        if self.first(uv) {
            self.color0.eval_uv(uv)
        } else {
            self.color1.eval_uv(uv)
        }
    }

    /// One value: Mitsuba's `eval_1`, with the squares swapped.
    #[inline]
    fn eval_1(&self, uv: Vec2) -> f32 {
        if self.first(uv) {
            self.color1.eval_1_uv(uv)
        } else {
            self.color0.eval_1_uv(uv)
        }
    }

    fn bounds(&self) -> (Rgb, Rgb) {
        let (a, b) = (self.color0.bounds(), self.color1.bounds());
        (a.0.min(b.0), a.1.max(b.1))
    }

    fn bounds_1(&self) -> (f32, f32) {
        let (a, b) = (self.color0.bounds_1(), self.color1.bounds_1());
        (a.0.min(b.0), a.1.max(b.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn board(to_uv: UvTransform) -> Checkerboard {
        Checkerboard {
            color0: Box::new(Texture::Constant(Rgb::new(1.0, 0.0, 0.0))),
            color1: Box::new(Texture::Constant(Rgb::new(0.0, 0.0, 1.0))),
            to_uv,
        }
    }

    /// The four squares of the unit square, and their repetition outside it
    /// (negative coordinates included), by hand.
    #[test]
    fn squares_alternate_with_color0_at_the_origin() {
        let b = board(UvTransform::IDENTITY);
        let (c0, c1) = (Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 1.0));
        for (u, v, want) in [
            (0.25, 0.25, c0),
            (0.75, 0.25, c1),
            (0.25, 0.75, c1),
            (0.75, 0.75, c0),
            (1.25, 0.25, c0),
            (-0.25, 0.25, c1),
            (-0.25, -0.25, c0),
            (3.75, -2.25, c0),
            (3.25, -2.25, c1),
        ] {
            assert_eq!(b.eval(Vec2::new(u, v)), want, "({u}, {v})");
        }
        // One value: the squares swap, the values are the greys'.
        let g = Checkerboard {
            color0: Box::new(Texture::Constant(Rgb::splat(0.4))),
            color1: Box::new(Texture::Constant(Rgb::splat(0.2))),
            to_uv: UvTransform::IDENTITY,
        };
        assert_eq!(g.eval_1(Vec2::new(0.25, 0.25)), 0.2);
        assert_eq!(g.eval_1(Vec2::new(0.75, 0.25)), 0.4);
        assert_eq!(b.bounds(), (Rgb::ZERO, Rgb::new(1.0, 0.0, 1.0)));
    }

    /// `to_uv` scales (four times as many squares), translates and rotates
    /// the coordinates before the lookup.
    #[test]
    fn to_uv_maps_the_coordinates_first() {
        let scaled = board(UvTransform {
            rows: [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
        });
        assert_eq!(scaled.eval(Vec2::new(0.125, 0.125)), scaled.color0.eval_uv(Vec2::ZERO));
        assert_eq!(scaled.eval(Vec2::new(0.375, 0.125)), scaled.color1.eval_uv(Vec2::ZERO));
        assert_eq!(scaled.eval(Vec2::new(0.625, 0.125)), scaled.color0.eval_uv(Vec2::ZERO));
        let shifted = board(UvTransform {
            rows: [[1.0, 0.0, 0.5], [0.0, 1.0, 0.0]],
        });
        assert_eq!(shifted.eval(Vec2::new(0.25, 0.25)), shifted.color1.eval_uv(Vec2::ZERO));
        // A quarter turn: (u, v) ↦ (−v, u).
        let turned = board(UvTransform {
            rows: [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0]],
        });
        assert_eq!(turned.eval(Vec2::new(0.25, 0.25)), turned.color1.eval_uv(Vec2::ZERO));
        assert_eq!(turned.eval(Vec2::new(0.25, 0.75)), turned.color0.eval_uv(Vec2::ZERO));
    }
}
