//! The group of shapes that instances place, and the instance: their
//! schemas (the builder places them, `scene::build`).

use crate::description::mitsuba::Mitsuba;
use crate::description::{Kind, Param, Schema, Type};
use crate::scene::transform;

pub const INSTANCE: Schema = Schema {
    kind: Kind::Shape,
    plugin: "instance",
    what: "instance",
    doc: "a group of shapes placed by an affine map",
    mitsuba: &["instance"],
    params: &[
        Param::new(
            "group",
            Type::String,
            "required",
            "name of a `[groups.NAME]` table: the shapes placed",
        )
        .penumbra_only(),
        Param::new(
            "transform",
            Type::Table(&transform::PARAMS),
            "identity",
            "placement of the group: any invertible affine map (shear and non-uniform scale included)",
        )
        .mitsuba("to_world"),
    ],
};

/// A group of shapes that instances place (`[groups.NAME]`; its shapes are
/// the node's children).
pub const SHAPEGROUP: Schema = Schema {
    kind: Kind::Shape,
    plugin: "shapegroup",
    what: "group",
    doc: "shapes that instances place, not rendered by themselves",
    mitsuba: &["shapegroup"],
    params: &[],
};

/// How Mitsuba's `instance` maps onto it.
pub const INSTANCE_MITSUBA: Mitsuba =
    Mitsuba::differs("`<ref id=\"g\"/>` to a shapegroup as `group = \"g\"`");

/// How Mitsuba's `shapegroup` maps onto it.
pub const SHAPEGROUP_MITSUBA: Mitsuba = Mitsuba::differs(
    "`[groups.ID]`; a shape in it may carry an `area` emitter, each instance an emitter of its own (Mitsuba refuses it)",
);
