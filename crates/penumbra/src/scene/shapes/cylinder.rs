//! The `cylinder` shape, an open tube between two end points: its schema
//! and builder (the shape is [`geometry::Cylinder`](crate::geometry::Cylinder)).

use super::{placed, uniform_scale, Loading, Placing, COMMON};
use crate::description::check::{finite3, positive};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Kind, Param, Props, Range, Schema, Type};
use crate::geometry::{Cylinder, Shape};
use crate::math::Mat4;
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "cylinder",
    what: "cylinder",
    doc: "an open tube between two end points",
    mitsuba: &["cylinder"],
    params: &[
        Param::new(
            "p0",
            Type::Vector,
            "[0, 0, 0]",
            "centre of the first end before the transform",
        ),
        Param::new(
            "p1",
            Type::Vector,
            "[0, 0, 1]",
            "centre of the second end before the transform, ≠ `p0`",
        ),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static cylinder may only be scaled uniformly)",
        )
        .range(Range::Positive),
        COMMON[0],
        COMMON[1],
        COMMON[2],
        COMMON[3],
        COMMON[4],
        COMMON[5],
        COMMON[6],
    ],
};

/// How Mitsuba's `cylinder` maps onto it.
pub const MITSUBA: Mitsuba =
    super::analytic(
    "only uniform scale outside a group (Mitsuba also takes an elliptic tube); `silhouette_sampling_weight` is read with no effect (it weights Mitsuba's sampling of derivatives)",
);

/// The tube of the parameters `p`, placed by `at`.
pub(super) fn build(p: &Props, at: &Placing, _: &mut Loading) -> Result<Shape, BuildError> {
    let p0 = finite3(p, "p0", [0.0; 3])?;
    let p1 = finite3(p, "p1", [0.0, 0.0, 1.0])?;
    let radius = positive(p, "radius", 1.0)?;
    let Some(c) = Cylinder::new(p0, p1, radius) else {
        return Err(p.error("p1", "p0 and p1 must differ").into());
    };
    let m = if at.moving { Mat4::IDENTITY } else { at.start };
    let s = uniform_scale(p, "cylinder", &m)?;
    Ok(Shape::Cylinder(placed(c, &m, s)))
}
