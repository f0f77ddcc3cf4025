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

/// Mitsuba's `obj`, `ply` and `serialized`: a `filename` is required;
/// `face_normals` (default false) is the opposite of `smooth`; an OBJ's
/// texture coordinates are flipped unless `flip_tex_coords` is false (what
/// Mitsuba's OBJ reader does), another file's `flip_tex_coords` is read
/// and not applied.
pub fn mesh(obj: &Object, node: &mut Node, base: &KeyPath) -> Result<(), SceneError> {
    if node.prop("path").is_none() {
        return Err(error_at(
            &obj.at,
            format!("{}: missing `filename`", obj.plugin),
        ));
    }
    let (faces, at) =
        get_bool(obj, "face_normals")?.map_or((false, obj.at.clone()), |(b, at)| (b, at.clone()));
    set(node, base, "smooth", &at, |p, at| {
        located(Value::Bool(!faces), p, at)
    });
    if obj.plugin == "obj" {
        if node.prop("flip_tex_coords").is_none() {
            set(node, base, "flip_tex_coords", &obj.at, |p, at| {
                located(Value::Bool(true), p, at)
            });
        }
    } else {
        node.props.retain(|p| p.name != "flip_tex_coords");
    }
    Ok(())
}
