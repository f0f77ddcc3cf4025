//! The lights of a scene (`[[lights]]` of a scene file): a point, spot or
//! directional light, an environment map or a sky is an emitter of its
//! own; a rectangle, sphere or disk light is a shape carrying an `area`
//! emitter, visible to rays but casting no shadow (so that it never blocks
//! its own light, as the thesis's lights do not).

use std::path::Path;

use super::shapes::quad;
use crate::description::check::{finite3_value, nonzero3_value, positive_value, required};
use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Kind, Param, Props, Range, Schema, Type};
use crate::emitter::{area, Constant, Directional, Emitter, Envmap, Point, Sky, Spot};
use crate::geometry::{Disk, Shape, Sphere};
use crate::math::Frame;

/// A parameter a light cannot do without.
const fn param(name: &'static str, ty: Type, doc: &'static str) -> Param {
    Param::new(name, ty, "required", doc)
}

pub const RECT: Schema = Schema {
    kind: Kind::Emitter,
    plugin: "rect",
    what: "rect light",
    doc: "a parallelogram emitting uniform radiance along `edge_u × edge_v`, casting no shadow",
    mitsuba: &[],
    params: &[
        param("origin", Type::Vector, "one corner"),
        param("edge_u", Type::Vector, "first edge"),
        param(
            "edge_v",
            Type::Vector,
            "second edge; the light emits along `edge_u × edge_v`",
        ),
        area::PARAMS[0],
        area::PARAMS[1],
        area::PARAMS[2],
        area::PARAMS[3],
    ],
};

pub const SPHERE: Schema = Schema {
    kind: Kind::Emitter,
    plugin: "sphere",
    what: "sphere light",
    doc: "a sphere emitting uniform radiance outward, casting no shadow",
    mitsuba: &[],
    params: &[
        param("center", Type::Vector, "its centre"),
        param("radius", Type::Number, "its radius > 0").range(Range::Positive),
        area::PARAMS[0],
        area::PARAMS[1],
        area::PARAMS[2],
        area::PARAMS[3],
    ],
};

pub const DISK: Schema = Schema {
    kind: Kind::Emitter,
    plugin: "disk",
    what: "disk light",
    doc: "a disk emitting uniform radiance along its normal, casting no shadow",
    mitsuba: &[],
    params: &[
        param("center", Type::Vector, "its centre"),
        param("normal", Type::Vector, "the direction it emits along"),
        param("radius", Type::Number, "its radius > 0").range(Range::Positive),
        area::PARAMS[0],
        area::PARAMS[1],
        area::PARAMS[2],
        area::PARAMS[3],
    ],
};

/// The emitters as the readers see them: Mitsuba's first, in the order
/// messages list them.
pub const PLUGINS: [Plugin; 10] = [
    Plugin::new(&Point::SCHEMA, Point::MITSUBA),
    Plugin::new(&Constant::SCHEMA, Constant::MITSUBA),
    Plugin::new(&area::SCHEMA, area::MITSUBA),
    Plugin::new(&Spot::SCHEMA, Spot::MITSUBA),
    Plugin::new(&Directional::SCHEMA, Directional::MITSUBA),
    Plugin::new(&Envmap::SCHEMA, Envmap::MITSUBA),
    Plugin::new(&RECT, Mitsuba::SAME),
    Plugin::new(&SPHERE, Mitsuba::SAME),
    Plugin::new(&DISK, Mitsuba::SAME),
    Plugin::new(&Sky::SCHEMA, Mitsuba::SAME),
];

/// Every emitter a scene file names: its lights, and the background's.
pub const SCHEMAS: [&Schema; 9] = [
    &Point::SCHEMA,
    &RECT,
    &SPHERE,
    &DISK,
    &Constant::SCHEMA,
    &Spot::SCHEMA,
    &Directional::SCHEMA,
    &Envmap::SCHEMA,
    &Sky::SCHEMA,
];

/// What a light of a scene file is: an emitter of its own, or a shape
/// carrying an `area` emitter (whose parameters are the light's others).
pub(super) enum Light {
    Emitter(Emitter),
    Shape(Shape),
}

/// The light `plugin` of the parameters `p`; `base_dir` anchors an
/// environment map's file.
pub(super) fn light(plugin: &str, p: &Props, base_dir: &Path) -> Result<Light, Invalid> {
    let emitter = match plugin {
        "point" => Emitter::Point(Point::build(p)?),
        "constant" => Emitter::Constant(Constant::build(p)?),
        "spot" => Emitter::Spot(Spot::build(p)?),
        "directional" => Emitter::Directional(Directional::build(p)?),
        "envmap" => Emitter::Envmap(Envmap::build(p, base_dir)?),
        "sky" => Emitter::Envmap(Sky::build(p)?.envmap()),
        "rect" => return Ok(Light::Shape(Shape::Quad(quad(p, "rect light")?))),
        "sphere" => {
            let center = required(p, p.numbers::<3>("center")?, "center", "sphere light")?;
            let center = finite3_value(p, "center", center)?;
            let radius = required(p, p.f32("radius")?, "radius", "sphere light")?;
            let radius = positive_value(p, "radius", radius)?;
            return Ok(Light::Shape(Shape::Sphere(Sphere::new(center, radius))));
        }
        "disk" => {
            let center = required(p, p.numbers::<3>("center")?, "center", "disk light")?;
            let center = finite3_value(p, "center", center)?;
            let normal = required(p, p.numbers::<3>("normal")?, "normal", "disk light")?;
            let normal = nonzero3_value(p, "normal", normal)?;
            let radius = required(p, p.f32("radius")?, "radius", "disk light")?;
            let radius = positive_value(p, "radius", radius)?;
            let frame = Frame::from_normal(normal.normalize());
            return Ok(Light::Shape(Shape::Disk(Disk::new(center, frame, radius))));
        }
        _ => return Err(p.node_error(format!("`{plugin}` is not a light a scene names by itself"))),
    };
    Ok(Light::Emitter(emitter))
}
