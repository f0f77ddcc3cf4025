//! The `disk` shape: its schema and builder (the shape is
//! [`geometry::Disk`](crate::geometry::Disk)).

use super::{placed, uniform_scale, Loading, Placing, COMMON};
use crate::description::check::{finite3, nonzero3_value, positive};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Kind, Param, Props, Range, Schema, Type};
use crate::geometry::{Disk, Shape};
use crate::math::{Frame, Vec3};
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "disk",
    what: "disk",
    doc: "a flat disk",
    mitsuba: &["disk"],
    params: &[
        Param::new(
            "center",
            Type::Vector,
            "[0, 0, 0]",
            "centre before the transform",
        )
        .penumbra_only(),
        Param::new(
            "normal",
            Type::Vector,
            "[0, 0, 1]",
            "the side it faces before the transform (non-zero)",
        )
        .penumbra_only(),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static disk may only be scaled uniformly)",
        )
        .range(Range::Positive)
        .penumbra_only(),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
        COMMON[5],
        COMMON[6],
    ],
};

/// How Mitsuba's `disk` maps onto it.
pub const MITSUBA: Mitsuba = super::analytic(
    "only uniform scale outside a group; `silhouette_sampling_weight` is read with no effect (it weights Mitsuba's sampling of derivatives)",
);

/// The disk of the parameters `p`, placed by `at`.
pub(super) fn build(p: &Props, at: &Placing, _: &mut Loading) -> Result<Shape, BuildError> {
    let center = finite3(p, "center", [0.0; 3])?;
    let normal = match p.numbers::<3>("normal")? {
        Some(n) => nonzero3_value(p, "normal", n)?.normalize(),
        None => Vec3::Z,
    };
    let radius = positive(p, "radius", 1.0)?;
    let frame = Frame::from_normal(normal);
    let disk = Disk::new(center, frame, radius);
    if at.as_written || at.moving {
        return Ok(Shape::Disk(disk));
    }
    let s = uniform_scale(p, "disk", &at.start)?;
    Ok(Shape::Disk(placed(disk, &at.start, s)))
}
