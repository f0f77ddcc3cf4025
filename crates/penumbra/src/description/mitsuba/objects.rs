//! Elements into objects: a plugin (`<shape type="sphere">`) with its typed
//! properties, nested objects and references, and the scene's ids.

use std::collections::{HashMap, HashSet};
use std::rc::Rc;

use super::parse::{self, check_attrs, clip, Element, Reader};
use super::values::{self, PropValue};
use crate::description::error::{KeyPath, Location, Origin, SceneError};

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

/// Where an object or a property was written: a tag of an XML file, or a
/// key of a dict (`sphere.bsdf.reflectance`).
#[derive(Clone, Debug, PartialEq)]
pub enum Place {
    File(Location),
    Key(KeyPath),
}

impl Place {
    /// The origin of a tree value made from what is written here, at the
    /// tree's key path `path`: a file's place is kept; a dict has none.
    pub fn origin(&self, path: KeyPath) -> Origin {
        match self {
            Place::File(at) => Origin::new(path, Some(at.clone())),
            Place::Key(_) => Origin::unlocated(path),
        }
    }

    /// The folder relative file names written here are read from: that of
    /// the XML file, or `base` for a dict.
    pub fn dir(&self, base: &std::path::Path) -> std::path::PathBuf {
        match self {
            Place::File(at) => at
                .file
                .parent()
                .map(|p| p.to_path_buf())
                .unwrap_or_default(),
            Place::Key(_) => base.to_path_buf(),
        }
    }
}

impl From<Location> for Place {
    fn from(at: Location) -> Self {
        Place::File(at)
    }
}

/// A problem at a place: `file:line:column: message`, or `key.path:
/// message` for a dict.
pub fn error_at(at: &Place, message: impl Into<String>) -> SceneError {
    match at {
        Place::File(at) => parse::error_at(at, message),
        Place::Key(path) if path.is_root() => SceneError::new(message),
        Place::Key(path) => SceneError::new(format!("{path}: {}", message.into())),
    }
}

/// A property: its name, value and places.
#[derive(Clone, Debug)]
pub struct Property {
    pub name: String,
    pub value: PropValue,
    /// The property's tag.
    pub at: Place,
}

/// A nested object or a reference to one.
#[derive(Clone, Debug)]
pub enum Child {
    /// Shared with the ids that name it, never copied.
    Object(Rc<Object>),
    Ref {
        id: String,
        at: Place,
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
    pub at: Place,
    /// Where `type` is written.
    pub plugin_at: Place,
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
    pub fn get(&self, id: &str, at: &Place) -> Result<&Object, SceneError> {
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
        return Err(parse::error_at(
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
        Some(a) => (a.value.clone(), Place::from(a.at.clone())),
        None => ("scene".to_string(), Place::from(e.at.clone())),
    };
    let mut obj = Object {
        tag: e.tag.clone(),
        plugin,
        id: e.get("id").map(str::to_string),
        props: Vec::new(),
        children: Vec::new(),
        at: e.at.clone().into(),
        plugin_at,
    };
    let mut aliases = Vec::new();
    // The properties' names so far: a set, so that an object of very many
    // is read in time linear in their number.
    let mut named = HashSet::new();
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
                        at: c.at.clone().into(),
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
                if !named.insert(name.clone()) {
                    return Err(parse::error_at(
                        &c.at,
                        format!("`{}` is given twice", clip(&name)),
                    ));
                }
                obj.props.push(Property {
                    name,
                    value,
                    at: c.at.clone().into(),
                });
            }
            "scene" => return Err(parse::error_at(&c.at, "<scene> inside a scene")),
            other => {
                return Err(parse::error_at(
                    &c.at,
                    format!("<{}> is not a tag of Mitsuba scenes", clip(other)),
                ))
            }
        }
        // An alias names an object already read.
        for a in aliases.drain(..) {
            let (src, dst) = (a.get("id").unwrap_or(""), a.get("as").unwrap_or(""));
            if ids.map.contains_key(dst) {
                return Err(parse::error_at(
                    &a.at,
                    format!("<alias>: the id `{}` is taken", clip(dst)),
                ));
            }
            ids.get(src, &a.at.clone().into())?;
            let target = Rc::clone(&ids.map[src]);
            ids.map.insert(dst.to_string(), target);
        }
    }
    // Objects live until the tree is made: no room beyond what they hold.
    obj.props.shrink_to_fit();
    obj.children.shrink_to_fit();
    if let Some(id) = obj.id.clone() {
        if ids.map.contains_key(&id) {
            let at = &e.attr("id").expect("an id").at;
            return Err(parse::error_at(
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
