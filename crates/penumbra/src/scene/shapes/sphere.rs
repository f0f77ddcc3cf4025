//! The `sphere` shape: its schema and builder (the shape is
//! [`geometry::Sphere`](crate::geometry::Sphere)).

use super::{placed, Loading, Placing, COMMON};
use crate::description::check::{finite3, positive};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::geometry::{Shape, Sphere};
use crate::math::{Mat4, Vec3};
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "sphere",
    what: "sphere",
    doc: "a sphere",
    mitsuba: &["sphere"],
    params: &[
        Param::new(
            "center",
            Type::Vector,
            "[0, 0, 0]",
            "centre before the transform",
        ),
        Param::new(
            "radius",
            Type::Number,
            "1",
            "radius > 0 before the transform (a static sphere may only be scaled uniformly)",
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

/// How Mitsuba's `sphere` maps onto it.
pub const MITSUBA: Mitsuba = super::analytic(
    "only uniform scale outside a group; `silhouette_sampling_weight` is read with no effect (it weights Mitsuba's sampling of derivatives)",
);

/// The sphere of the parameters `p`, placed by `at`.
pub(super) fn build(p: &Props, at: &Placing, _: &mut Loading) -> Result<Shape, BuildError> {
    let center = finite3(p, "center", [0.0; 3])?;
    let radius = positive(p, "radius", 1.0)?;
    Ok(sphere(p, center, radius, &at.start, at.as_written || at.moving)?)
}

/// A static sphere stays analytic under translation, rotation and uniform
/// scale; anything else would make an ellipsoid, which we do not support.
/// `as_given`: the sphere is taken as given (a moving one is placed at
/// each ray's time).
fn sphere(
    p: &Props,
    center: Vec3,
    radius: f32,
    m: &Mat4,
    as_given: bool,
) -> Result<Shape, Invalid> {
    if as_given {
        return Ok(Shape::Sphere(Sphere::new(center, radius)));
    }
    let (scale, _, _) = m.to_scale_rotation_translation();
    let s = scale.abs();
    if (s.max_element() - s.min_element()) > 1e-4 * s.max_element() {
        return Err(p.error("transform", "a sphere can only be scaled uniformly"));
    }
    Ok(Shape::Sphere(placed(Sphere::new(center, radius), m, s.x)))
}

