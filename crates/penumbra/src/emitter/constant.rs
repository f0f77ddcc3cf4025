//! `constant`: radiance arriving from every direction at infinity — the
//! scene's background (`render.background`), what rays that hit nothing
//! see (Mitsuba 3's `constant` emitter).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `radiance` | colour ≥ 0 | **required** | the radiance of every direction |

use crate::description::check::{nonneg3, required};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::math::Rgb;

#[derive(Clone, Copy, Debug)]
pub struct Constant {
    pub radiance: Rgb,
}

impl Constant {
    pub const SCHEMA: Schema = Schema {
        kind: Kind::Emitter,
        plugin: "constant",
        what: "constant emitter",
        params: &[Param {
            name: "radiance",
            ty: Type::Colour,
            default: "required",
            doc: "the radiance of every direction, ≥ 0",
        }],
    };

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
}
