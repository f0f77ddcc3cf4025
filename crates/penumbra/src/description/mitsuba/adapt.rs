//! The parts of the mapping of Mitsuba's plugins that their schemas cannot
//! say, each named by the plugin it completes (as its
//! [`Adapt::Node`](super::registry::Adapt::Node)): what Mitsuba means
//! otherwise, written into the node the schema made.

use super::mapper::{get_bool, get_transform, located, set, vec3};
use super::objects::{error_at, Object};
use super::transform;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::{Node, Value};

/// Mitsuba's `rectangle`: the square [−1, 1]² at z = 0 through `to_world`,
/// as a quad's `origin`, `edge_u` and `edge_v`. Mitsuba's normal is the
/// transformed +z; a mirroring transform would turn `edge_u × edge_v` the
/// other way, so it takes the edges in the other order.
pub fn rectangle(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let (m, at) = match get_transform(obj, "to_world")? {
        Some((m, at)) => (m, at.clone()),
        None => (transform::IDENTITY, obj.at.clone()),
    };
    let origin = transform::point(&m, [-1.0, -1.0, 0.0]);
    let mut u = transform::vector(&m, [2.0, 0.0, 0.0]);
    let mut v = transform::vector(&m, [0.0, 2.0, 0.0]);
    if transform::det3(&m) < 0.0 {
        std::mem::swap(&mut u, &mut v);
    }
    set(node, base, "origin", &at, |p, at| vec3(origin, p, at));
    set(node, base, "edge_u", &at, |p, at| vec3(u, p, at));
    set(node, base, "edge_v", &at, |p, at| vec3(v, p, at));
    Ok(())
}

/// Mitsuba's `obj`, `ply` and `serialized`: `face_normals` (default false)
/// is the opposite of `smooth`; an OBJ's texture coordinates are flipped
/// unless `flip_tex_coords` is false (what Mitsuba's OBJ reader does), a
/// PLY's only when it is true (its reader's default is false), and a
/// `.serialized` file's `flip_tex_coords` is read and not applied, as
/// Mitsuba's reader does not apply it.
pub fn mesh(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let (faces, at) =
        get_bool(obj, "face_normals")?.map_or((false, obj.at.clone()), |(b, at)| (b, at.clone()));
    set(node, base, "smooth", &at, |p, at| {
        located(Value::Bool(!faces), p, at)
    });
    match obj.plugin.as_str() {
        "obj" if node.prop("flip_tex_coords").is_none() => {
            set(node, base, "flip_tex_coords", &obj.at, |p, at| {
                located(Value::Bool(true), p, at)
            });
        }
        "serialized" => node.props.retain(|p| p.name != "flip_tex_coords"),
        _ => {}
    }
    Ok(())
}

/// A colour `name` of 1 in every channel where Mitsuba's emitter is not
/// given one (Penumbra's requires it).
fn unit_colour(obj: &Object, node: &mut Node, base: &KeyPath, name: &str) {
    if node.prop(name).is_none() {
        set(node, base, name, &obj.at, |p, at| vec3([1.0; 3], p, at));
    }
}

/// A direction or position `name` that `to_world` may give instead, as
/// `from_world` makes it of the matrix; both is an error (`what` names
/// the emitter); `default` where neither is given (`None`: left out).
fn placed(
    obj: &Object,
    node: &mut Node,
    base: &KeyPath,
    (name, what): (&str, &str),
    from_world: fn(&transform::Mat4) -> [f64; 3],
    default: Option<[f64; 3]>,
) -> Result<(), SceneError> {
    match (node.prop(name).is_some(), get_transform(obj, "to_world")?) {
        (true, Some((_, at))) => Err(error_at(
            at,
            format!("give the {what} `{name}` or `to_world`, not both"),
        )),
        (false, Some((m, at))) => {
            let v = from_world(&m);
            set(node, base, name, at, |p, at| vec3(v, p, at));
            Ok(())
        }
        (false, None) => {
            if let Some(v) = default {
                set(node, base, name, &obj.at, |p, at| vec3(v, p, at));
            }
            Ok(())
        }
        (true, None) => Ok(()),
    }
}

/// Mitsuba's `point`: its `position` or `to_world`'s image of the origin
/// (the origin without either), `intensity` 1 unless given.
pub fn point(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let origin = |m: &transform::Mat4| transform::point(m, [0.0; 3]);
    placed(
        obj,
        node,
        base,
        ("position", "point light"),
        origin,
        Some([0.0; 3]),
    )?;
    unit_colour(obj, node, base, "intensity");
    Ok(())
}

/// Mitsuba's `spot`: `to_world`'s images of the origin and of +z as its
/// `position` and `look_at`, and of the direction +y as its `up` (which
/// orients its `texture`).
pub fn spot(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    if let Some((m, at)) = get_transform(obj, "to_world")? {
        let position = transform::point(&m, [0.0; 3]);
        let look_at = transform::point(&m, [0.0, 0.0, 1.0]);
        let up = transform::vector(&m, [0.0, 1.0, 0.0]);
        set(node, base, "position", at, |p, at| vec3(position, p, at));
        set(node, base, "look_at", at, |p, at| vec3(look_at, p, at));
        if obj
            .children
            .iter()
            .any(|(name, _)| name.as_deref() == Some("texture"))
        {
            set(node, base, "up", at, |p, at| vec3(up, p, at));
        }
    }
    Ok(())
}

/// Mitsuba's `directional`: its `direction` or `to_world`'s image of +z.
pub fn directional(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let z = |m: &transform::Mat4| transform::vector(m, [0.0, 0.0, 1.0]);
    placed(obj, node, base, ("direction", "directional light"), z, None)
}

/// Mitsuba's `area`: `radiance` 1 unless given (as a value or a texture).
pub fn area(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let textured = obj
        .children
        .iter()
        .any(|(n, _)| n.as_deref() == Some("radiance"));
    if !textured {
        unit_colour(obj, node, base, "radiance");
    }
    Ok(())
}

/// Mitsuba's `projector`: `to_world`'s images of the origin, of one unit
/// along +z and of +y as `position`, `look_at` and `up`; a `to_world` that
/// scales, shears or mirrors (whose 3 × 3 part is no rotation) is refused,
/// since the light's frame would not say it.
pub fn projector(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    let Some((m, at)) = get_transform(obj, "to_world")? else {
        return Ok(());
    };
    let column = |k: usize| {
        let mut e = [0.0; 3];
        e[k] = 1.0;
        transform::vector(&m, e)
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let rigid = (0..3).all(|i| {
        (0..3).all(|j| {
            let want = if i == j { 1.0 } else { 0.0 };
            (dot(column(i), column(j)) - want).abs() < 1e-4
        })
    }) && transform::det3(&m) > 0.0;
    if !rigid {
        return Err(error_at(
            at,
            "the projector's `to_world` must be a rotation and a translation (a `lookat`); \
             one that scales, shears or mirrors is not supported",
        ));
    }
    let position = transform::point(&m, [0.0; 3]);
    let look_at = transform::point(&m, [0.0, 0.0, 1.0]);
    let up = column(1);
    set(node, base, "position", at, |p, at| vec3(position, p, at));
    set(node, base, "look_at", at, |p, at| vec3(look_at, p, at));
    set(node, base, "up", at, |p, at| vec3(up, p, at));
    Ok(())
}
