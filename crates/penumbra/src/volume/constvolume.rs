//! `constvolume`: the same value everywhere in the unit cube that
//! `transform` places (Mitsuba 3's `constvolume`). A medium bounded by its
//! extinction volume is bounded by that box. Where a medium's volume
//! parameter is written as a plain number or colour, it is this volume.
//!
//! Read as one value, 3 numbers give their mean (as Mitsuba's `eval_1`);
//! the largest value is the largest channel.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `value` | number or 3 numbers ≥ 0 | `1` | the value |
//! | `transform` | table | identity | the placement of the unit cube (Mitsuba's `to_world`) |

use super::{world_box, VolumeModel, Volumes};
use crate::description::mitsuba::Mitsuba;
use crate::description::placement;
use crate::description::{Invalid, Kind, Param, Props, Schema, Type, Value};
use crate::math::{Aabb, Mat4, Rgb, Vec3};

/// Its parameters.
const SCHEMA: Schema = Schema {
    kind: Kind::Volume,
    plugin: "constvolume",
    what: "constant volume",
    doc: "one number or 3 numbers everywhere",
    mitsuba: &["constvolume"],
    params: &[
        Param::new(
            "value",
            Type::Scale,
            "1",
            "the value: one number (the same in each channel) or 3 numbers, finite and ≥ 0",
        ),
        Param::new(
            "transform",
            Type::Table(&placement::PARAMS),
            "identity",
            "placement of the unit cube the volume fills",
        )
        .mitsuba("to_world"),
    ],
};

/// The constant volume (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct ConstVolume {
    pub value: Rgb,
    pub to_local: Mat4,
    pub bbox: Aabb,
}

impl ConstVolume {
    /// `value` in the unit cube placed by `to_world`.
    pub fn new(value: Rgb, to_world: Mat4) -> ConstVolume {
        ConstVolume {
            value,
            to_local: to_world.inverse(),
            bbox: world_box(&to_world),
        }
    }
}

impl VolumeModel for ConstVolume {
    const NAME: &'static str = "constvolume";
    const SCHEMA: Schema = SCHEMA;
    const MITSUBA: Mitsuba = Mitsuba::differs("`value` is a number or 3 numbers, ≥ 0, not a texture");

    fn build(p: &Props, _volumes: &Volumes) -> Result<ConstVolume, Invalid> {
        let value = match p.get("value") {
            None => Rgb::ONE,
            Some(prop) => match &prop.value.value {
                Value::Array(_) => {
                    let xs = crate::description::props::numbers(&prop.value, 3)?;
                    Rgb::new(xs[0], xs[1], xs[2])
                }
                _ => Rgb::splat(crate::description::props::number(&prop.value)?),
            },
        };
        if !value.is_finite() || value.min_element() < 0.0 {
            return Err(p.error(
                "value",
                format!("must be finite and ≥ 0, got {:?}", value.to_array()),
            ));
        }
        let to_world = placement::read(p, "transform")?.unwrap_or(Mat4::IDENTITY);
        Ok(ConstVolume::new(value, to_world))
    }

    fn eval(&self, _p: Vec3) -> Rgb {
        self.value
    }

    /// The mean of the channels (Mitsuba's `eval_1` of a constant).
    fn eval_1(&self, _p: Vec3) -> f32 {
        self.value.element_sum() / 3.0
    }

    fn max(&self) -> f32 {
        self.value.max_element()
    }

    fn bbox(&self) -> Aabb {
        self.bbox
    }

    fn to_local(&self) -> Mat4 {
        self.to_local
    }

    fn max_in(&self, _lo: Vec3, _hi: Vec3) -> f32 {
        self.max()
    }
}
