//! The `rectangle` shape, Mitsuba's: the square [−1, 1]² at z = 0 placed
//! by the transform. Its schema and builder.

use super::{placed, Loading, Placing, COMMON};
use crate::description::mitsuba::Mitsuba;
use crate::description::{Kind, Props, Schema};
use crate::geometry::quad::Quad;
use crate::geometry::Shape;
use crate::math::{Mat4, Vec3};
use crate::scene::BuildError;

pub const SCHEMA: Schema = Schema {
    kind: Kind::Shape,
    plugin: "rectangle",
    what: "rectangle",
    doc: "Mitsuba's rectangle: the square [−1, 1]² at z = 0 placed by the transform, facing +z",
    mitsuba: &[],
    params: &[COMMON[0], COMMON[1], COMMON[2], COMMON[3], COMMON[4], COMMON[5], COMMON[6]],
};

/// Read as Mitsuba writes it.
pub const MITSUBA: Mitsuba = super::analytic(
    "`silhouette_sampling_weight` is read with no effect (it weights Mitsuba's sampling of derivatives)",
);

/// The rectangle placed by `at`.
pub(super) fn build(_: &Props, at: &Placing, _: &mut Loading) -> Result<Shape, BuildError> {
    let q = Quad::new(Vec3::new(-1.0, -1.0, 0.0), 2.0 * Vec3::X, 2.0 * Vec3::Y);
    Ok(Shape::Quad(if at.moving {
        q
    } else {
        transform_rectangle(&q, &at.start)
    }))
}

/// Mitsuba's rectangle under `m`: its normal is the transformed +z, so a
/// mirroring transform takes the edges in the other order.
fn transform_rectangle(q: &Quad, m: &Mat4) -> Quad {
    let t = placed(*q, m, 1.0);
    if m.determinant() < 0.0 {
        Quad::new(t.origin, t.edge_v, t.edge_u)
    } else {
        t
    }
}

