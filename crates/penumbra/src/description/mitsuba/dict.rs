//! Mitsuba 3's dict form (`mi.load_dict`) read into the [objects] an XML
//! file gives, so that the same [`plugins`](super::plugins) mapping lowers both.
//!
//! A dict is an object: its `type` names the plugin (`"scene"` at the
//! root), `id` its id, and every other key a property or a nested object:
//!
//! | value | read as |
//! |---|---|
//! | boolean, integer, float, string | `<boolean>`, `<integer>`, `<float>`, `<string>` |
//! | a list of 3 numbers | `<point>` / `<vector>` |
//! | a list of 4 lists of 4 numbers | `<transform>` (its matrix, row by row, affine and not singular) |
//! | `{"type": "rgb", "value": [r, g, b]}` (or one number) | `<rgb>` |
//! | `{"type": "spectrum", "value": x}` or `[[nm, x], ...]` | `<spectrum>` |
//! | `{"type": "ref", "id": "name"}` | `<ref id="name">` |
//! | any other dict with a `type` | a nested object, its tag (`shape`, `bsdf`, `medium`, `phase`, `volume`...) the one of its plugin |
//!
//! As in Mitsuba, an object of the scene's own dict takes its key as its
//! id unless it gives `id`, so that a `ref` names it by its key; a nested
//! object has the id it gives, if any (its key is the parameter it is, as
//! a `<texture name="reflectance">`). A key holds no `.`. Every object and
//! value is placed at its key path (`sphere.bsdf.reflectance`), which
//! errors name.
//!
//! [objects]: super::objects

use std::fmt::{self, Write as _};
use std::rc::Rc;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use super::mapping::mitsuba_names;
use super::objects::{error_at, Child, Ids, Object, Place, Property, OBJECT_TAGS};
use super::parse::clip;
use super::registry::Registry;
use super::spectrum::{self, Spectrum};
use super::transform::{self, Mat4};
use super::values::PropValue;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::Kind;

/// How deep dicts and lists nest in a scene dict (real scenes: five).
pub const MAX_DEPTH: usize = 32;

/// A value of a scene dict, its entries in the dict's order (which is the
/// order of the scene's objects).
#[derive(Clone, Debug, PartialEq)]
pub enum DictValue {
    Bool(bool),
    Int(i64),
    Float(f64),
    String(String),
    List(Vec<DictValue>),
    Dict(Vec<(String, DictValue)>),
}

impl DictValue {
    /// What the value is, for messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            DictValue::Bool(_) => "a boolean",
            DictValue::Int(_) => "an integer",
            DictValue::Float(_) => "a float",
            DictValue::String(_) => "a string",
            DictValue::List(_) => "a list",
            DictValue::Dict(_) => "a dict",
        }
    }

    /// The value as JSON text, entries in order, every float written so
    /// that it reads back to the same bits ([`from_json`](Self::from_json)).
    pub fn to_json(&self) -> String {
        let mut out = String::new();
        self.write_json(&mut out);
        out
    }

    fn write_json(&self, out: &mut String) {
        let quote = |s: &str| serde_json::Value::String(s.to_string()).to_string();
        match self {
            DictValue::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            DictValue::Int(i) => {
                let _ = write!(out, "{i}");
            }
            // Finite (checked where the value is made); `{:?}` keeps a
            // float's point (`1.0`), so that it reads back as a float.
            DictValue::Float(x) => {
                let _ = write!(out, "{x:?}");
            }
            DictValue::String(s) => out.push_str(&quote(s)),
            DictValue::List(items) => {
                out.push('[');
                for (i, v) in items.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    v.write_json(out);
                }
                out.push(']');
            }
            DictValue::Dict(entries) => {
                out.push('{');
                for (i, (k, v)) in entries.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    out.push_str(&quote(k));
                    out.push(':');
                    v.write_json(out);
                }
                out.push('}');
            }
        }
    }

    /// Reads [`to_json`](Self::to_json)'s text, keeping the order of every
    /// dict's entries.
    pub fn from_json(text: &str) -> Result<DictValue, String> {
        let mut de = serde_json::Deserializer::from_str(text);
        let v = DictValue::deserialize(&mut de).map_err(|e| e.to_string())?;
        de.end().map_err(|e| e.to_string())?;
        Ok(v)
    }
}

impl<'de> Deserialize<'de> for DictValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(DictVisitor)
    }
}

struct DictVisitor;

impl<'de> Visitor<'de> for DictVisitor {
    type Value = DictValue;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a boolean, number, string, list or dict")
    }

    fn visit_bool<E>(self, b: bool) -> Result<DictValue, E> {
        Ok(DictValue::Bool(b))
    }

    fn visit_i64<E>(self, i: i64) -> Result<DictValue, E> {
        Ok(DictValue::Int(i))
    }

    fn visit_u64<E: de::Error>(self, u: u64) -> Result<DictValue, E> {
        i64::try_from(u)
            .map(DictValue::Int)
            .map_err(|_| E::custom(format!("the integer {u} is out of range")))
    }

    fn visit_f64<E: de::Error>(self, x: f64) -> Result<DictValue, E> {
        if x.is_finite() {
            Ok(DictValue::Float(x))
        } else {
            Err(E::custom("a number is not finite"))
        }
    }

    fn visit_str<E>(self, s: &str) -> Result<DictValue, E> {
        Ok(DictValue::String(s.to_string()))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<DictValue, A::Error> {
        let mut items = Vec::new();
        while let Some(v) = seq.next_element()? {
            items.push(v);
        }
        Ok(DictValue::List(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<DictValue, A::Error> {
        let mut entries = Vec::new();
        while let Some((k, v)) = map.next_entry::<String, DictValue>()? {
            entries.push((k, v));
        }
        Ok(DictValue::Dict(entries))
    }
}

/// Every plugin the mapping reads, by tag, in the order messages list them.
fn plugin_tags(registry: Registry) -> [(&'static str, Vec<&'static str>); 12] {
    let of = |kind| mitsuba_names(registry(kind));
    [
        ("integrator", of(Kind::Integrator)),
        ("sensor", of(Kind::Sensor)),
        ("film", of(Kind::Film)),
        ("rfilter", of(Kind::Filter)),
        ("sampler", of(Kind::Sampler)),
        ("shape", of(Kind::Shape)),
        ("bsdf", of(Kind::Bsdf)),
        ("emitter", of(Kind::Emitter)),
        ("texture", of(Kind::Texture)),
        ("volume", of(Kind::Volume)),
        ("medium", of(Kind::Medium)),
        ("phase", of(Kind::Phase)),
    ]
}

/// The tag of a plugin (`sphere`: `shape`), as Mitsuba finds it from the
/// plugin's class.
fn tag_of(plugin: &str, registry: Registry) -> Option<&'static str> {
    plugin_tags(registry)
        .into_iter()
        .find(|(_, names)| names.contains(&plugin))
        .map(|(tag, _)| tag)
}

/// The scene's dict into its object, registering every id.
pub fn read_scene(
    d: &DictValue,
    ids: &mut Ids,
    registry: Registry,
) -> Result<Rc<Object>, SceneError> {
    let root = KeyPath::root();
    let DictValue::Dict(entries) = d else {
        return Err(error_at(
            &Place::Key(root),
            format!("a scene is a dict, not {}", d.type_name()),
        ));
    };
    let mut reader = DictReader {
        ids,
        depth: 0,
        registry,
    };
    let plugin = reader.plugin(entries, &root)?;
    if plugin != "scene" {
        return Err(error_at(
            &Place::Key(root.key("type")),
            format!(
                "the root's type is `{}`; a scene dict's is `scene`",
                clip(&plugin)
            ),
        ));
    }
    reader.object(entries, "scene", plugin, None, &root)
}

struct DictReader<'a> {
    ids: &'a mut Ids,
    depth: usize,
    registry: Registry,
}

impl DictReader<'_> {
    /// The dict's `type`.
    fn plugin(
        &self,
        entries: &[(String, DictValue)],
        path: &KeyPath,
    ) -> Result<String, SceneError> {
        match entries.iter().find(|(k, _)| k == "type") {
            Some((_, DictValue::String(s))) => Ok(s.clone()),
            Some((_, v)) => Err(error_at(
                &Place::Key(path.key("type")),
                format!("must be a string (the plugin), got {}", v.type_name()),
            )),
            None => Err(error_at(
                &Place::Key(path.clone()),
                "missing key `type` (every object of a scene dict names its plugin)",
            )),
        }
    }

    /// The object of `entries` at `path`, of tag `tag` and plugin
    /// `plugin`, its id `key_id` unless it gives one.
    fn object(
        &mut self,
        entries: &[(String, DictValue)],
        tag: &str,
        plugin: String,
        key_id: Option<&str>,
        path: &KeyPath,
    ) -> Result<Rc<Object>, SceneError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(error_at(
                &Place::Key(path.clone()),
                format!("objects nest more than {MAX_DEPTH} deep"),
            ));
        }
        let is_scene = tag == "scene";
        let mut obj = Object {
            tag: tag.to_string(),
            plugin,
            id: key_id.map(str::to_string),
            props: Vec::new(),
            children: Vec::new(),
            at: Place::Key(path.clone()),
            plugin_at: Place::Key(if is_scene {
                path.clone()
            } else {
                path.key("type")
            }),
        };
        for (key, value) in entries {
            let at = path.key(key);
            let place = Place::Key(at.clone());
            match key.as_str() {
                "type" => continue,
                "id" => match value {
                    DictValue::String(s) => {
                        obj.id = Some(s.clone());
                        continue;
                    }
                    v => {
                        return Err(error_at(
                            &place,
                            format!("must be a string, got {}", v.type_name()),
                        ))
                    }
                },
                _ => {}
            }
            if key.contains('.') {
                return Err(error_at(
                    &place,
                    "a key holds no `.`, which separates the keys of a path (use `_`)",
                ));
            }
            let value = match value {
                DictValue::Bool(b) => PropValue::Bool(*b),
                DictValue::Int(i) => PropValue::Int(*i),
                DictValue::Float(x) => PropValue::Float(*x),
                DictValue::String(s) => PropValue::String(s.clone()),
                DictValue::List(items) => list(items, &place)?,
                DictValue::Dict(inner) => {
                    let kind = self.plugin(inner, &at)?;
                    match kind.as_str() {
                        "rgb" => rgb(inner, &at)?,
                        "spectrum" => spectrum_value(inner, &at)?,
                        "ref" => {
                            if is_scene {
                                return Err(error_at(
                                    &place,
                                    "a `ref` directly in the scene is not supported: declare \
                                     the object there",
                                ));
                            }
                            let id = reference(inner, &at)?;
                            obj.children
                                .push((Some(key.clone()), Child::Ref { id, at: place }));
                            continue;
                        }
                        "scene" => return Err(error_at(&place, "a scene inside a scene")),
                        _ => {
                            let Some(child_tag) = tag_of(&kind, self.registry) else {
                                return Err(unknown_plugin(&kind, &at, self.registry));
                            };
                            let id = is_scene.then_some(key.as_str());
                            let child = self.object(inner, child_tag, kind, id, &at)?;
                            obj.children.push((Some(key.clone()), Child::Object(child)));
                            continue;
                        }
                    }
                }
            };
            obj.props.push(Property {
                name: key.clone(),
                value,
                at: place,
            });
        }
        self.depth -= 1;
        let obj = Rc::new(obj);
        if let Some(id) = &obj.id {
            if self.ids.map.contains_key(id) {
                let at = match entries.iter().any(|(k, _)| k == "id") {
                    true => path.key("id"),
                    false => path.clone(),
                };
                return Err(error_at(
                    &Place::Key(at),
                    format!("the id `{}` is given twice", clip(id)),
                ));
            }
            self.ids.map.insert(id.clone(), Rc::clone(&obj));
        }
        Ok(obj)
    }
}

/// A plugin no tag has: the error naming what is read.
fn unknown_plugin(plugin: &str, path: &KeyPath, registry: Registry) -> SceneError {
    let kinds: Vec<String> = plugin_tags(registry)
        .iter()
        .map(|(tag, names)| format!("{tag}: {}", names.join(", ")))
        .collect();
    let other = OBJECT_TAGS.contains(&plugin);
    error_at(
        &Place::Key(path.key("type")),
        format!(
            "`{}` is not a plugin Penumbra reads{}; it reads {}",
            clip(plugin),
            if other {
                " (a type names a plugin, not its kind)"
            } else {
                ""
            },
            kinds.join("; ")
        ),
    )
}

/// A number of a list.
fn list_number(v: &DictValue) -> Option<f64> {
    match v {
        DictValue::Int(i) => Some(*i as f64),
        DictValue::Float(x) => Some(*x),
        _ => None,
    }
}

/// A list: 3 numbers (a point or vector) or 4 rows of 4 (a transform).
fn list(items: &[DictValue], at: &Place) -> Result<PropValue, SceneError> {
    let numbers: Option<Vec<f64>> = items.iter().map(list_number).collect();
    if let Some(v) = &numbers {
        if v.len() == 3 {
            return Ok(PropValue::Vector([v[0], v[1], v[2]]));
        }
    }
    let rows: Option<Vec<Vec<f64>>> = items
        .iter()
        .map(|row| match row {
            DictValue::List(r) => r.iter().map(list_number).collect(),
            _ => None,
        })
        .collect();
    match rows {
        Some(rows) if rows.len() == 4 && rows.iter().all(|r| r.len() == 4) => {
            let m: Mat4 = std::array::from_fn(|i| std::array::from_fn(|j| rows[i][j]));
            transform_checked(&m).map_err(|m| error_at(at, m))?;
            Ok(PropValue::Transform(m))
        }
        _ => {
            let shape = match (&numbers, &rows) {
                (Some(v), _) => format!("{} numbers", v.len()),
                (None, Some(rows)) => {
                    let lens: Vec<String> = rows.iter().map(|r| r.len().to_string()).collect();
                    format!("{} rows of [{}] numbers", rows.len(), lens.join(", "))
                }
                (None, None) => "a list of other values".to_string(),
            };
            Err(error_at(
                at,
                format!(
                    "expected 3 numbers (a point or vector) or a 4×4 matrix, 4 rows of 4 \
                     numbers (a transform); got {shape}"
                ),
            ))
        }
    }
}

/// Whether a transform's matrix is affine and not singular (the error).
pub fn transform_checked(m: &Mat4) -> Result<(), &'static str> {
    if !transform::is_affine(m) {
        return Err("the last row of a transform must be 0 0 0 1 (an affine transform)");
    }
    if transform::is_singular(m) {
        return Err("the transform's matrix is singular (it flattens space)");
    }
    Ok(())
}

/// Refuses a key of an `rgb`, `spectrum` or `ref` dict not in `allowed`.
fn only_keys(
    entries: &[(String, DictValue)],
    path: &KeyPath,
    what: &str,
    allowed: &[&str],
) -> Result<(), SceneError> {
    match entries.iter().find(|(k, _)| !allowed.contains(&k.as_str())) {
        Some((k, _)) => Err(error_at(
            &Place::Key(path.key(k)),
            format!(
                "a `{what}` dict takes {}, not `{}`",
                allowed
                    .iter()
                    .map(|a| format!("`{a}`"))
                    .collect::<Vec<_>>()
                    .join(" and "),
                clip(k)
            ),
        )),
        None => Ok(()),
    }
}

fn entry<'e>(entries: &'e [(String, DictValue)], key: &str) -> Option<&'e DictValue> {
    entries.iter().find(|(k, _)| k == key).map(|(_, v)| v)
}

/// `{"type": "rgb", "value": [r, g, b]}`, or one number for all three.
fn rgb(entries: &[(String, DictValue)], path: &KeyPath) -> Result<PropValue, SceneError> {
    only_keys(entries, path, "rgb", &["type", "value"])?;
    let at = Place::Key(path.key("value"));
    match entry(entries, "value") {
        None => Err(error_at(&Place::Key(path.clone()), "missing key `value`")),
        Some(v) => {
            if let Some(x) = list_number(v) {
                return Ok(PropValue::Rgb([x; 3]));
            }
            let c: Option<Vec<f64>> = match v {
                DictValue::List(items) => items.iter().map(list_number).collect(),
                _ => None,
            };
            match c {
                Some(c) if c.len() == 3 => Ok(PropValue::Rgb([c[0], c[1], c[2]])),
                _ => Err(error_at(&at, "expected 3 numbers (or one for all three)")),
            }
        }
    }
}

/// `{"type": "spectrum", "value": x}` or `[[wavelength, value], ...]`.
fn spectrum_value(
    entries: &[(String, DictValue)],
    path: &KeyPath,
) -> Result<PropValue, SceneError> {
    only_keys(entries, path, "spectrum", &["type", "value"])?;
    let at = Place::Key(path.key("value"));
    let Some(v) = entry(entries, "value") else {
        return Err(error_at(&Place::Key(path.clone()), "missing key `value`"));
    };
    if let Some(x) = list_number(v) {
        return Ok(PropValue::Spectrum(Spectrum::Constant(x)));
    }
    let pairs: Option<Vec<(f64, f64)>> = match v {
        DictValue::List(items) => items
            .iter()
            .map(|p| match p {
                DictValue::List(p) if p.len() == 2 => {
                    Some((list_number(&p[0])?, list_number(&p[1])?))
                }
                _ => None,
            })
            .collect(),
        _ => None,
    };
    let Some(pairs) = pairs else {
        return Err(error_at(
            &at,
            "expected a number or a list of [wavelength, value] pairs",
        ));
    };
    spectrum::samples_checked(pairs)
        .map(PropValue::Spectrum)
        .map_err(|m| error_at(&at, m))
}

/// The id of `{"type": "ref", "id": "name"}`.
fn reference(entries: &[(String, DictValue)], path: &KeyPath) -> Result<String, SceneError> {
    only_keys(entries, path, "ref", &["type", "id"])?;
    match entry(entries, "id") {
        Some(DictValue::String(s)) => Ok(s.clone()),
        Some(v) => Err(error_at(
            &Place::Key(path.key("id")),
            format!("must be a string, got {}", v.type_name()),
        )),
        None => Err(error_at(&Place::Key(path.clone()), "missing key `id`")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(json: &str) -> Result<(Rc<Object>, Ids), String> {
        let d = DictValue::from_json(json).expect("valid JSON");
        let mut ids = Ids::default();
        read_scene(&d, &mut ids, super::super::registry::tests::registry)
            .map(|o| (o, ids))
            .map_err(|e| e.to_string())
    }

    fn err(json: &str) -> String {
        match read(json) {
            Ok(_) => panic!("{json} should be refused"),
            Err(e) => e,
        }
    }

    fn child(obj: &Object, i: usize) -> &Object {
        match &obj.children[i].1 {
            Child::Object(o) => o,
            Child::Ref { id, .. } => panic!("a ref to {id}"),
        }
    }

    #[test]
    fn json_text_keeps_the_order_and_the_bits() {
        let text = r#"{"z":1,"a":{"type":"rgb","value":[0.1,2.5e-300,-0.0]},"m":[true,"s",3.0]}"#;
        let v = DictValue::from_json(text).unwrap();
        let DictValue::Dict(entries) = &v else {
            panic!("{v:?}")
        };
        let keys: Vec<&str> = entries.iter().map(|(k, _)| k.as_str()).collect();
        assert_eq!(keys, ["z", "a", "m"]);
        assert_eq!(entries[0].1, DictValue::Int(1));
        assert_eq!(DictValue::from_json(&v.to_json()).unwrap(), v);
        let DictValue::List(m) = &entries[2].1 else {
            panic!()
        };
        // A float stays a float through the text.
        assert_eq!(m[2], DictValue::Float(3.0));
        assert!(DictValue::from_json("[1e999]").is_err());
        assert!(DictValue::from_json("[18446744073709551615]").is_err());
    }

    #[test]
    fn values_become_the_properties_an_xml_file_gives() {
        let (scene, ids) = read(
            r#"{"type": "scene",
                "red": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.2, 0.2]}},
                "ball": {"type": "sphere", "center": [0, 1, 0.5], "radius": 0.8,
                         "flip_normals": false, "bsdf": {"type": "ref", "id": "red"}},
                "floor": {"type": "rectangle",
                          "to_world": [[2, 0, 0, 1], [0, 2, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]],
                          "material": {"type": "diffuse", "id": "grey",
                                       "reflectance": {"type": "spectrum", "value": 0.5}}},
                "lamp": {"type": "point", "intensity": {"type": "spectrum",
                         "value": [[400, 1], [700, 2]]}, "position": [1, 2, 3]}}"#,
        )
        .unwrap();
        assert_eq!(
            (scene.tag.as_str(), scene.plugin.as_str()),
            ("scene", "scene")
        );
        let tags: Vec<(&str, &str)> = (0..4)
            .map(|i| {
                let c = child(&scene, i);
                (c.tag.as_str(), c.plugin.as_str())
            })
            .collect();
        assert_eq!(
            tags,
            [
                ("bsdf", "diffuse"),
                ("shape", "sphere"),
                ("shape", "rectangle"),
                ("emitter", "point")
            ]
        );
        // The scene's objects are named by their keys, nested ones by
        // their own `id` only.
        let mut named: Vec<&str> = ids.map.keys().map(String::as_str).collect();
        named.sort_unstable();
        assert_eq!(named, ["ball", "floor", "grey", "lamp", "red"]);
        let red = child(&scene, 0);
        assert_eq!(
            red.prop("reflectance").unwrap().value,
            PropValue::Rgb([0.7, 0.2, 0.2])
        );
        let ball = child(&scene, 1);
        assert_eq!(
            ball.prop("center").unwrap().value,
            PropValue::Vector([0.0, 1.0, 0.5])
        );
        assert_eq!(ball.prop("radius").unwrap().value, PropValue::Float(0.8));
        assert_eq!(
            ball.prop("flip_normals").unwrap().value,
            PropValue::Bool(false)
        );
        assert_eq!(
            ball.prop("radius").unwrap().at,
            Place::Key(KeyPath::root().key("ball").key("radius"))
        );
        match &ball.children[0] {
            (Some(name), Child::Ref { id, at }) => {
                assert_eq!((name.as_str(), id.as_str()), ("bsdf", "red"));
                assert_eq!(*at, Place::Key(KeyPath::root().key("ball").key("bsdf")));
            }
            other => panic!("{other:?}"),
        }
        let floor = child(&scene, 2);
        let PropValue::Transform(m) = floor.prop("to_world").unwrap().value else {
            panic!()
        };
        assert_eq!(transform::point(&m, [1.0, 1.0, 0.0]), [3.0, 2.0, 0.0]);
        let grey = child(floor, 0);
        assert_eq!(grey.id.as_deref(), Some("grey"));
        assert_eq!(
            grey.prop("reflectance").unwrap().value,
            PropValue::Spectrum(Spectrum::Constant(0.5))
        );
        assert_eq!(
            child(&scene, 3).prop("intensity").unwrap().value,
            PropValue::Spectrum(Spectrum::Samples(vec![(400.0, 1.0), (700.0, 2.0)]))
        );
    }

    #[test]
    fn bad_dicts_are_refused_at_their_key_path() {
        let cases = [
            (r#"[1]"#, "a scene is a dict, not a list"),
            (r#"{"type": "shape"}"#, "type: the root's type is `shape`"),
            (r#"{"a": 1}"#, "missing key `type`"),
            (
                r#"{"type": "scene", "s": {"type": "volpath"}}"#,
                "s.type: `volpath` is not a plugin Penumbra reads; it reads integrator: path",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "bsdf": {"type": "diffuse",
                   "reflectance": {"type": "rgb", "value": [1, 2]}}}}"#,
                "s.bsdf.reflectance.value: expected 3 numbers",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "to_world": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}}"#,
                "s.to_world: expected 3 numbers (a point or vector) or a 4×4 matrix, 4 rows of 4 \
                 numbers (a transform); got 3 rows of [3, 3, 3] numbers",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "to_world": [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}}"#,
                "s.to_world: the transform's matrix is singular",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "center": [1, 2]}}"#,
                "s.center: expected 3 numbers",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "b": {"type": "ref"}}}"#,
                "s.b: missing key `id`",
            ),
            (
                r#"{"type": "scene", "s": {"type": "sphere", "b": {"type": "ref", "id": "x", "k": 1}}}"#,
                "s.b.k: a `ref` dict takes `type` and `id`, not `k`",
            ),
            (
                r#"{"type": "scene", "r": {"type": "ref", "id": "x"}}"#,
                "r: a `ref` directly in the scene is not supported",
            ),
            (
                r#"{"type": "scene", "a.b": {"type": "sphere"}}"#,
                "a.b: a key holds no `.`",
            ),
            (
                r#"{"type": "scene", "a": {"type": "sphere"}, "b": {"type": "disk", "id": "a"}}"#,
                "b.id: the id `a` is given twice",
            ),
            (
                r#"{"type": "scene", "a": {"type": 3}}"#,
                "a.type: must be a string (the plugin), got an integer",
            ),
            (
                r#"{"type": "scene", "a": {"type": "shape"}}"#,
                "(a type names a plugin, not its kind)",
            ),
            (
                r#"{"type": "scene", "a": {"type": "point", "intensity": {"type": "spectrum", "value": [[500, 1], [400, 2]]}}}"#,
                "a.intensity.value: the wavelengths of a spectrum must increase",
            ),
        ];
        for (json, expected) in cases {
            let e = err(json);
            assert!(e.contains(expected), "{json}\n  gave {e}\n  not {expected}");
        }
        let deep = format!(
            "{{\"type\": \"scene\", \"s\": {}{}}}",
            "{\"type\": \"sphere\", \"b\": ".repeat(40),
            "1".to_string() + &"}".repeat(40)
        );
        assert!(err(&deep).contains("objects nest more than 32 deep"));
    }
}
