//! The `cube` shape, Mitsuba's: the 24-vertex mesh of [−1, 1]³ placed by
//! the transform. Its schema and builder.

use super::{Loading, Placing, COMMON};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Kind, Props, Schema};
use crate::geometry::cube::cube;
use crate::geometry::{MeshShape, Shape};
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "cube",
    what: "cube",
    doc: "Mitsuba's cube: the 24-vertex mesh of [−1, 1]³ placed by the transform",
    mitsuba: &["cube"],
    params: &[COMMON[0], COMMON[1], COMMON[2], COMMON[3], COMMON[4], COMMON[5], COMMON[6]],
};

/// Read as Mitsuba writes it.
pub const MITSUBA: Mitsuba = Mitsuba::SAME;

/// The cube placed by `at` (baked into world space when it does not move).
pub(super) fn build(_: &Props, at: &Placing, load: &mut Loading) -> Result<Shape, BuildError> {
    load.meshes.push(if at.moving {
        cube()
    } else {
        cube().transformed(&at.start)
    });
    Ok(Shape::MeshShape(MeshShape::new((load.meshes.len() - 1) as u32)))
}
