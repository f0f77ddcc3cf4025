//! The `quad` shape, a parallelogram of a corner and two edges, which
//! Mitsuba's `rectangle` is read as: its schema and builder (the shape is
//! [`geometry::quad::Quad`](crate::geometry::quad::Quad)).

use super::{placed, Loading, Placing, COMMON};
use crate::description::check::{finite3_value, nonzero3_value, required};
use crate::description::mitsuba::registry::Adapt;
use crate::description::mitsuba::{adapt, Mitsuba};
use crate::description::{Invalid, Kind, Param, Props, Schema, Type};
use crate::geometry::quad::Quad;
use crate::geometry::Shape;
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "quad",
    what: "quad",
    doc: "a parallelogram of a corner and two edges",
    mitsuba: &["rectangle"],
    params: &[
        Param::new("origin", Type::Vector, "required", "one corner").penumbra_only(),
        Param::new("edge_u", Type::Vector, "required", "first edge").penumbra_only(),
        Param::new(
            "edge_v",
            Type::Vector,
            "required",
            "second edge, not parallel to `edge_u`",
        )
        .penumbra_only(),
        COMMON[0],
        COMMON[1].penumbra_only(),
        COMMON[2],
        COMMON[3],
        COMMON[4],
        COMMON[5],
        COMMON[6],
    ],
};

/// How Mitsuba's `rectangle` maps onto it.
pub const MITSUBA: Mitsuba = Mitsuba {
    differences: "the square [−1, 1]² at z = 0 through `to_world` as `origin`, `edge_u`, `edge_v`, ordered so that `edge_u × edge_v` is Mitsuba's normal; `silhouette_sampling_weight` is read with no effect (it weights Mitsuba's sampling of derivatives)",
    reads: &["to_world", "silhouette_sampling_weight"],
    adapt: Some(Adapt::Node(adapt::rectangle)),
};

/// The quad of the parameters `p`, placed by `at`.
pub(super) fn build(p: &Props, at: &Placing, _: &mut Loading) -> Result<Shape, BuildError> {
    let q = quad(p, "quad")?;
    Ok(Shape::Quad(if at.as_written || at.moving {
        q
    } else {
        placed(q, &at.start, 1.0)
    }))
}

/// The parallelogram of `origin`, `edge_u` and `edge_v` (`what` names the
/// object in messages).
fn quad(p: &Props, what: &str) -> Result<Quad, Invalid> {
    let origin = required(p, p.numbers::<3>("origin")?, "origin", what)?;
    let origin = finite3_value(p, "origin", origin)?;
    let eu = required(p, p.numbers::<3>("edge_u")?, "edge_u", what)?;
    let eu = nonzero3_value(p, "edge_u", eu)?;
    let ev = required(p, p.numbers::<3>("edge_v")?, "edge_v", what)?;
    let ev = nonzero3_value(p, "edge_v", ev)?;
    if eu.cross(ev).length() <= 1e-6 * eu.length() * ev.length() {
        return Err(p.error("edge_v", "edge_u and edge_v must not be parallel"));
    }
    Ok(Quad::new(origin, eu, ev))
}

