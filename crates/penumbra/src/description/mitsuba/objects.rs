//! Elements into objects: a plugin (`<shape type="sphere">`) with its typed
//! properties, nested objects and references, and the scene's ids.

use std::collections::HashMap;
use std::rc::Rc;

use super::parse::{check_attrs, clip, error_at, Element, Reader};
use super::values::{self, PropValue};
use crate::description::error::{Location, SceneError};

/// The tags of objects, which Mitsuba calls plugin interfaces.
pub const OBJECT_TAGS: &[&str] = &[
    "scene",
    "integrator",
    "sensor",
    "film",
    "sampler",
    "rfilter",
    "shape",
    "bsdf",
    "emitter",
    "texture",
    "medium",
    "phase",
    "volume",
];

/// A property: its name, value and places.
#[derive(Clone, Debug)]
pub struct Property {
    pub name: String,
    pub value: PropValue,
    /// The property's tag.
    pub at: Location,
}

/// A nested object or a reference to one.
#[derive(Clone, Debug)]
pub enum Child {
    /// Shared with the ids that name it, never copied.
    Object(Rc<Object>),
    Ref {
        id: String,
        at: Location,
    },
}

/// An object and what it holds.
#[derive(Clone, Debug)]
pub struct Object {
    /// `shape`, `bsdf`, ...
    pub tag: String,
    /// The `type` (the plugin); `scene` for the scene.
    pub plugin: String,
    pub id: Option<String>,
    pub props: Vec<Property>,
    pub children: Vec<(Option<String>, Child)>,
    pub at: Location,
    /// Where `type` is written.
    pub plugin_at: Location,
}

impl Object {
    pub fn prop(&self, name: &str) -> Option<&Property> {
        self.props.iter().find(|p| p.name == name)
    }
}

/// Every id and alias and the object it names.
#[derive(Default)]
pub struct Ids {
    pub map: HashMap<String, Rc<Object>>,
}

impl Ids {
    pub fn get(&self, id: &str, at: &Location) -> Result<&Object, SceneError> {
        self.map
            .get(id)
            .map(Rc::as_ref)
            .ok_or_else(|| error_at(at, format!("<ref>: no object has the id `{}`", clip(id))))
    }
}

/// The scene element into its object, registering every id.
pub fn read_scene(
    root: &Element,
    reader: &Reader,
    ids: &mut Ids,
) -> Result<Rc<Object>, SceneError> {
    if root.tag != "scene" {
        return Err(error_at(
            &root.at,
            format!(
                "the root element is <{}>; a scene file's is <scene>",
                clip(&root.tag)
            ),
        ));
    }
    object(root, reader, ids)
}

fn object(e: &Element, reader: &Reader, ids: &mut Ids) -> Result<Rc<Object>, SceneError> {
    let is_scene = e.tag == "scene";
    if is_scene {
        check_attrs(e, &["id", "name"], &[])?;
    } else {
        check_attrs(e, &["type", "id", "name"], &["type"])?;
    }
    let (plugin, plugin_at) = match e.attr("type") {
        Some(a) => (a.value.clone(), a.at.clone()),
        None => ("scene".to_string(), e.at.clone()),
    };
    let mut obj = Object {
        tag: e.tag.clone(),
        plugin,
        id: e.get("id").map(str::to_string),
        props: Vec::new(),
        children: Vec::new(),
        at: e.at.clone(),
        plugin_at,
    };
    let mut aliases = Vec::new();
    for c in &e.children {
        let name = c.get("name").map(str::to_string);
        match c.tag.as_str() {
            t if OBJECT_TAGS.contains(&t) && t != "scene" => {
                let child = object(c, reader, ids)?;
                obj.children.push((name, Child::Object(child)));
            }
            "ref" => {
                check_attrs(c, &["id", "name"], &["id"])?;
                let id = c.get("id").expect("checked").to_string();
                obj.children.push((
                    name,
                    Child::Ref {
                        id,
                        at: c.at.clone(),
                    },
                ));
            }
            "alias" => {
                check_attrs(c, &["id", "as"], &["id", "as"])?;
                aliases.push(c);
            }
            "integer" | "float" | "boolean" | "string" | "point" | "vector" | "rgb"
            | "spectrum" | "transform" => {
                let value = values::read(c, reader)?;
                let name = name.expect("checked by the value's reader");
                if obj.props.iter().any(|p| p.name == name) {
                    return Err(error_at(&c.at, format!("`{}` is given twice", clip(&name))));
                }
                obj.props.push(Property {
                    name,
                    value,
                    at: c.at.clone(),
                });
            }
            "scene" => return Err(error_at(&c.at, "<scene> inside a scene")),
            other => {
                return Err(error_at(
                    &c.at,
                    format!("<{}> is not a tag of Mitsuba scenes", clip(other)),
                ))
            }
        }
        // An alias names an object already read.
        for a in aliases.drain(..) {
            let (src, dst) = (a.get("id").unwrap_or(""), a.get("as").unwrap_or(""));
            if ids.map.contains_key(dst) {
                return Err(error_at(
                    &a.at,
                    format!("<alias>: the id `{}` is taken", clip(dst)),
                ));
            }
            ids.get(src, &a.at)?;
            let target = Rc::clone(&ids.map[src]);
            ids.map.insert(dst.to_string(), target);
        }
    }
    if let Some(id) = obj.id.clone() {
        if ids.map.contains_key(&id) {
            let at = &e.attr("id").expect("an id").at;
            return Err(error_at(
                at,
                format!("the id `{}` is given twice", clip(&id)),
            ));
        }
        let obj = Rc::new(obj);
        ids.map.insert(id, Rc::clone(&obj));
        return Ok(obj);
    }
    Ok(Rc::new(obj))
}
