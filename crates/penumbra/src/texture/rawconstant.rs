//! `rawconstant`: the same value everywhere, taken as written (Mitsuba 3's
//! `rawconstant`). Unlike a plain colour it is not read as a colour: no
//! range is checked, so negative values and values above 1 are kept, and
//! nothing is converted. `value` is one number or 3 numbers; one number
//! stands for itself in each channel.
//!
//! Read as one value (a roughness), one number is that number. 3 numbers,
//! which Mitsuba refuses to read as one value, give the grey's value or the
//! luminance, as a plain colour does.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `value` | number or vector | **required** | the value, one number or 3 numbers, finite |

use super::common::one;
use super::{TextureModel, Textures};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Schema, Type, Value};
use crate::math::{Rgb, Vec2};

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Texture,
    plugin: "rawconstant",
    what: "raw constant texture",
    doc: "one number or 3 numbers everywhere, taken as they are: no colour check, negative values allowed",
    mitsuba: &["rawconstant"],
    params: &[Param::new(
        "value",
        Type::Scale,
        "required",
        "the value: one number (the same in each channel) or 3 numbers, finite, any sign",
    )],
};

/// The raw constant (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawConstant {
    /// The value in each channel.
    pub value: Rgb,
    /// The value read as one value.
    pub one: f32,
}

impl RawConstant {
    /// One number, the same in each channel.
    pub fn number(x: f32) -> RawConstant {
        RawConstant {
            value: Rgb::splat(x),
            one: x,
        }
    }

    /// 3 numbers.
    pub fn rgb(c: Rgb) -> RawConstant {
        RawConstant {
            value: c,
            one: one(c),
        }
    }
}

impl TextureModel for RawConstant {
    const NAME: &'static str = "rawconstant";
    const SCHEMA: Schema = SCHEMA;
    const MITSUBA: Mitsuba =
        Mitsuba::differs("3 numbers read as one value give their grey or luminance (Mitsuba refuses)");

    fn build(p: &Props, _textures: &Textures) -> Result<RawConstant, Invalid> {
        let Some(prop) = p.get("value") else {
            return Err(p.node_error("missing field `value` (one number or 3 numbers)"));
        };
        let out = match &prop.value.value {
            Value::Array(_) => {
                let xs = crate::description::props::numbers(&prop.value, 3)?;
                RawConstant::rgb(Rgb::new(xs[0], xs[1], xs[2]))
            }
            _ => RawConstant::number(crate::description::props::number(&prop.value)?),
        };
        if !out.value.is_finite() {
            return Err(p.error("value", "expected finite numbers"));
        }
        Ok(out)
    }

    #[inline]
    fn eval(&self, _uv: Vec2) -> Rgb {
        self.value
    }

    #[inline]
    fn eval_1(&self, _uv: Vec2) -> f32 {
        self.one
    }

    fn bounds(&self) -> (Rgb, Rgb) {
        (self.value, self.value)
    }

    fn bounds_1(&self) -> (f32, f32) {
        (self.one, self.one)
    }
}
