//! The state and the helpers of the mapping of Mitsuba's objects onto
//! Penumbra's plugins ([`plugins`](super::plugins)): what has been made so
//! far, and the readers of an object's properties, each value placed at
//! its tag.

use std::collections::HashSet;

use super::objects::{error_at, Child, Ids, Object, Place, Property};
use super::parse::{clip, Reader};
use super::registry::Registry;
use super::spectrum::{self, Use};
use super::transform::Mat4;
use super::values::PropValue;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::{Located, Node, Prop, Value};

pub(super) fn render() -> KeyPath {
    KeyPath::root().key("render")
}

/// The mapping's state: the scene's ids, the reader of its files and the
/// plugins it maps onto, and the nodes made so far.
pub(super) struct Out<'a> {
    pub ids: &'a Ids,
    pub reader: &'a Reader<'a>,
    pub registry: Registry,
    /// Unknown parameters are warnings, not errors (`--lenient`).
    pub lenient: bool,
    pub warnings: &'a mut Vec<String>,
    pub integrator: Option<Node>,
    pub sensor: Option<Node>,
    /// The sensor asked for, and how many the scene has given so far.
    pub sensors: (usize, usize),
    /// The integrator's `path_sampler` for the sampler read, and where.
    pub path_sampler: Option<(&'static str, Place)>,
    pub background: Option<Node>,
    pub bsdfs: Vec<Node>,
    /// The scene's media (`media.ID`), each mapped once.
    pub media: Vec<Node>,
    /// The scene's textures (`textures.ID`), and the ids of those declared
    /// in the scene, which a `<ref>` names rather than copies.
    pub textures: Vec<Node>,
    pub texture_ids: HashSet<String>,
    /// The scene's volumes (`volumes.ID`).
    pub volumes: Vec<Node>,
    /// The ids the scene's shapes (and those of its groups) refer to by
    /// `<ref>`: an `area` emitter declared in the scene under one of them
    /// lights those shapes.
    pub shape_refs: HashSet<String>,
    pub names: HashSet<String>,
    pub shapes: Vec<Node>,
    pub lights: Vec<Node>,
    pub default_material: [Option<String>; 2],
}

/// `what` is not among `supported`.
pub(super) fn unsupported(obj: &Object, what: &str, supported: &[&str]) -> SceneError {
    error_at(
        &obj.plugin_at,
        format!(
            "{what} `{}` is not supported; supported: {}",
            clip(&obj.plugin),
            supported.join(", ")
        ),
    )
}

pub(super) fn located(value: Value, path: KeyPath, at: &Place) -> Located<Value> {
    Located::new(value, at.origin(path))
}

/// A float without a negative zero (which a file never means).
pub(super) fn float(x: f64, path: KeyPath, at: &Place) -> Located<Value> {
    located(Value::Float(x + 0.0), path, at)
}

pub(super) fn vec3(v: [f64; 3], path: KeyPath, at: &Place) -> Located<Value> {
    let items = (0..3).map(|i| float(v[i], path.index(i), at)).collect();
    located(Value::Array(items), path, at)
}

pub(super) fn matrix(m: &Mat4, path: KeyPath, at: &Place) -> Located<Value> {
    rows(m, path, at)
}

/// A matrix as an array of its rows, each an array of numbers.
pub(super) fn rows<const C: usize>(m: &[[f64; C]], path: KeyPath, at: &Place) -> Located<Value> {
    let rows = m
        .iter()
        .enumerate()
        .map(|(r, values)| {
            let row = path.index(r);
            let items = (0..C).map(|c| float(values[c], row.index(c), at)).collect();
            located(Value::Array(items), row, at)
        })
        .collect();
    located(Value::Array(rows), path, at)
}

/// Sets `name` on `node`, whose key path is `base`, from the tag at `at`.
pub(super) fn set(
    node: &mut Node,
    base: &KeyPath,
    name: &str,
    at: &Place,
    make: impl FnOnce(KeyPath, &Place) -> Located<Value>,
) {
    let path = base.key(name);
    let key = at.origin(path.clone());
    node.props.push(Prop::new(name, key, make(path, at)));
}

pub(super) fn type_error(p: &Property, expected: &str) -> SceneError {
    error_at(
        &p.at,
        format!(
            "`{}` must be {expected}, got {}",
            clip(&p.name),
            p.value.type_name()
        ),
    )
}

/// The property `name` of `obj` read by `read` (`None`: of the wrong type,
/// `expected`), with the place of its tag.
pub(super) fn get<'o, T>(
    obj: &'o Object,
    name: &str,
    expected: &str,
    read: impl Fn(&'o PropValue) -> Option<T>,
) -> Result<Option<(T, &'o Place)>, SceneError> {
    match obj.prop(name) {
        None => Ok(None),
        Some(p) => match read(&p.value) {
            Some(v) => Ok(Some((v, &p.at))),
            None => Err(type_error(p, expected)),
        },
    }
}

pub(super) fn get_float<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<(f64, &'o Place)>, SceneError> {
    get(obj, name, "a float", |v| match v {
        PropValue::Float(x) => Some(*x),
        PropValue::Int(i) => Some(*i as f64),
        _ => None,
    })
}

pub(super) fn get_int<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<(i64, &'o Place)>, SceneError> {
    get(obj, name, "an integer", |v| match v {
        PropValue::Int(i) => Some(*i),
        _ => None,
    })
}

pub(super) fn get_bool<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<(bool, &'o Place)>, SceneError> {
    get(obj, name, "a boolean", |v| match v {
        PropValue::Bool(b) => Some(*b),
        _ => None,
    })
}

pub(super) fn get_string<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<(&'o str, &'o Place)>, SceneError> {
    get(obj, name, "a string", |v| match v {
        PropValue::String(s) => Some(s.as_str()),
        _ => None,
    })
}

pub(super) fn get_vector<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<([f64; 3], &'o Place)>, SceneError> {
    get(obj, name, "a point or vector", |v| match v {
        PropValue::Vector(v) => Some(*v),
        _ => None,
    })
}

pub(super) fn get_transform<'o>(
    obj: &'o Object,
    name: &str,
) -> Result<Option<(Mat4, &'o Place)>, SceneError> {
    get(obj, name, "a transform", |v| match v {
        PropValue::Transform(m) => Some(*m),
        _ => None,
    })
}

/// A colour: `<rgb>`, `<spectrum>` or a number, converted as Mitsuba's RGB
/// variants convert it for `usage`.
pub(super) fn get_color<'o>(
    obj: &'o Object,
    name: &str,
    usage: Use,
) -> Result<Option<([f64; 3], &'o Place)>, SceneError> {
    let Some(p) = obj.prop(name) else {
        return Ok(None);
    };
    let rgb = match &p.value {
        PropValue::Rgb(c) => *c,
        PropValue::Float(x) => [*x; 3],
        PropValue::Int(i) => [*i as f64; 3],
        PropValue::Spectrum(s) => spectrum::to_rgb(s, usage),
        _ => return Err(type_error(p, "an rgb colour, a spectrum or a float")),
    };
    if rgb.iter().any(|c| !c.is_finite()) {
        return Err(error_at(
            &p.at,
            format!("`{}` is not a finite colour", clip(name)),
        ));
    }
    Ok(Some((rgb, &p.at)))
}

impl Out<'_> {
    /// Refuses a property of `obj` not in `known` (with `lenient`, warns
    /// that it is ignored).
    pub(super) fn no_props(&mut self, obj: &Object, known: &[&str]) -> Result<(), SceneError> {
        for p in &obj.props {
            if !known.contains(&p.name.as_str()) {
                let reads = if known.is_empty() {
                    "no parameters".to_string()
                } else {
                    known.join(", ")
                };
                let e = error_at(
                    &p.at,
                    format!(
                        "`{}` is not a parameter of the {} `{}` that Penumbra reads (it reads {reads})",
                        clip(&p.name),
                        obj.tag,
                        clip(&obj.plugin)
                    ),
                );
                if !self.lenient {
                    return Err(e);
                }
                self.warnings.push(format!("{e}; ignored (--lenient)"));
            }
        }
        Ok(())
    }

    pub(super) fn no_children(&self, obj: &Object) -> Result<(), SceneError> {
        match children(self.ids, obj)?.first() {
            None => Ok(()),
            Some(c) => Err(error_at(
                &c.at,
                format!(
                    "a <{}> inside the {} `{}` is not supported",
                    c.tag,
                    obj.tag,
                    clip(&obj.plugin)
                ),
            )),
        }
    }

    /// `bsdf_N`, the first such name that is neither an id nor taken.
    pub(super) fn fresh_name(&self) -> String {
        (1..)
            .map(|n| format!("bsdf_{n}"))
            .find(|n| !self.names.contains(n) && !self.ids.map.contains_key(n))
            .expect("a free name")
    }
}

/// The objects `obj` holds, references resolved.
pub(super) fn children<'o>(ids: &'o Ids, obj: &'o Object) -> Result<Vec<&'o Object>, SceneError> {
    obj.children
        .iter()
        .map(|(_, c)| match c {
            Child::Object(o) => Ok(o.as_ref()),
            Child::Ref { id, at } => ids.get(id, at),
        })
        .collect()
}

pub(super) fn obj_has(obj: &Object, name: &str) -> bool {
    obj.prop(name).is_some()
}

/// The folder of the file `obj`'s `filename` is written in (`base` for a
/// dict).
pub(super) fn file_dir(obj: &Object, base: &std::path::Path) -> std::path::PathBuf {
    obj.prop("filename").map_or(&obj.at, |p| &p.at).dir(base)
}
