//! The mapping of a Mitsuba object through the schema of the Penumbra
//! plugin that reads it (see [`registry`](super::registry)): the plugin
//! found by its Mitsuba name, each parameter read under Mitsuba's name for
//! it and converted as its type says — a colour from `<rgb>`, `<spectrum>`
//! or a number (a colour in [0, 1] and a texture's colours as a
//! reflectance, an emitter's colours as an emission, any other colour — a
//! conductor's index — as an unbounded value), a number, an integer, a boolean, a string (a
//! file name found as a mesh's is and written relative to the scene's
//! folder), a transform (a placement's 4 × 4, or `to_uv`'s upper-left 2 ×
//! 2 and translation) — and a parameter the schema requires checked.

use std::rc::Rc;

use super::mapper::{
    children, file_dir, float, get_bool, get_color, get_float, get_int, get_string, get_transform,
    get_vector, located, matrix, rows, set, type_error, unsupported, vec3, Out,
};
use super::objects::{error_at, Child, Object, Place};
use super::parse::clip;
use super::registry::{Adapt, Mapper, Plugin};
use super::spectrum::Use;
use super::values::PropValue;
use crate::description::error::{KeyPath, SceneError};
use crate::description::schema::{MitsubaKey, Param, Range, Schema, Type};
use crate::description::tree::{Kind, Located, Node, Prop, Value};

/// The Mitsuba names of a kind's plugins, in the registry's order.
pub(super) fn mitsuba_names(plugins: &[Plugin]) -> Vec<&'static str> {
    plugins
        .iter()
        .flat_map(|p| p.names.iter().copied())
        .collect()
}

/// The plugin of `kind` that reads `obj`, or the error naming those there
/// are (`what`: the tag in the message).
pub(super) fn plugin_of(
    plugins: &'static [Plugin],
    obj: &Object,
    what: &str,
) -> Result<&'static Plugin, SceneError> {
    plugins
        .iter()
        .find(|p| p.reads(&obj.plugin))
        .ok_or_else(|| unsupported(obj, what, &mitsuba_names(plugins)))
}

/// The node of `obj`, a plugin of `kind` declared in the scene as `id`,
/// from its table at `base` (made by the kind's table mapping): the
/// table's `type` becomes the node's plugin, its other keys the node's.
pub(super) fn declared(
    kind: Kind,
    id: String,
    obj: &Object,
    table: Located<Value>,
    base: KeyPath,
) -> Node {
    let Value::Table(mut props) = table.value else {
        unreachable!("a plugin's mapping makes a table")
    };
    let mut node = Node::new(kind, obj.plugin.clone(), obj.at.origin(base));
    if let Some(i) = props.iter().position(|p| p.name == "type") {
        node.plugin_origin = props.remove(i).value.origin;
    }
    node.id = Some(id);
    node.props = props;
    node
}

/// Refuses a property of `obj`, a plugin of kind `what` held as a table,
/// that `plugin` does not read (through its schema or its mapping).
pub(super) fn table_props(obj: &Object, plugin: &Plugin, what: &str) -> Result<(), SceneError> {
    let mut known = mitsuba_keys(plugin.schema);
    known.extend(plugin.mitsuba.reads);
    match obj.props.iter().find(|p| !known.contains(&p.name.as_str())) {
        None => Ok(()),
        Some(p) => Err(error_at(
            &p.at,
            format!(
                "`{}` is not a parameter of the {what} `{}` that Penumbra reads (it reads {})",
                clip(&p.name),
                clip(&obj.plugin),
                known.join(", ")
            ),
        )),
    }
}

/// The Mitsuba properties a schema reads: every parameter's Mitsuba name
/// but those set by nested objects.
pub(super) fn mitsuba_keys(schema: &Schema) -> Vec<&'static str> {
    schema
        .params
        .iter()
        .filter(|p| !p.ty.is_held() && p.mitsuba != MitsubaKey::Any)
        .filter_map(|p| p.mitsuba_name())
        .collect()
}

/// Refuses `node`, made of `obj` through `schema`, without a parameter the
/// schema requires (but the materials a schema holds, counted apart):
/// `plugin: missing `key``, at the object, under Mitsuba's name.
/// True if `obj` holds a texture as the parameter `p` (which the reader
/// sets from its texture children after the parameters).
pub(super) fn texture_child(obj: &Object, p: &Param) -> bool {
    let key = p.mitsuba_name().unwrap_or(p.name);
    p.texturable() && obj.children.iter().any(|(n, _)| n.as_deref() == Some(key))
}

pub(super) fn required(obj: &Object, schema: &Schema, node: &Node) -> Result<(), SceneError> {
    let missing = schema
        .params
        .iter()
        .filter(|p| p.default == "required" && !p.ty.is_held())
        .find(|p| node.prop(p.name).is_none() && !texture_child(obj, p));
    match missing {
        None => Ok(()),
        Some(p) => Err(error_at(
            &obj.at,
            format!(
                "{}: missing `{}`",
                clip(&obj.plugin),
                p.mitsuba_name().unwrap_or(p.name)
            ),
        )),
    }
}

/// The integrators' choice of emitter for next-event estimation.
const LIGHT_SAMPLER: &str = "light_sampler";

impl Out<'_> {
    /// The node of an object of `kind` at `base`, through the schema of
    /// the plugin of that kind that reads its plugin and the plugin's own
    /// adapter.
    pub(super) fn mapped(
        &mut self,
        kind: Kind,
        obj: &Object,
        base: KeyPath,
    ) -> Result<Node, SceneError> {
        let plugin = plugin_of((self.registry)(kind), obj, kind.name())?;
        let schema = plugin.schema;
        let mut known = mitsuba_keys(schema);
        known.extend(plugin.mitsuba.reads);
        self.no_props(obj, &known)?;
        let mut node = Node::new(kind, schema.plugin, obj.at.origin(base.clone()));
        node.plugin_origin = obj.plugin_at.origin(base.key("type"));
        self.params(obj, schema, &mut node, &base)?;
        if kind == Kind::Integrator && schema.params.iter().any(|p| p.name == LIGHT_SAMPLER) {
            // Mitsuba chooses the emitter of next-event estimation
            // uniformly.
            set(&mut node, &base, LIGHT_SAMPLER, &obj.at, |p, at| {
                located(Value::String("uniform".into()), p, at)
            });
        }
        match plugin.mitsuba.adapt {
            Some(Adapt::Node(adapt)) => adapt(obj, &mut node, &base)?,
            Some(Adapt::Held(adapt)) => adapt(self, obj, &mut node, &base)?,
            Some(Adapt::Object(_)) | None => {}
        }
        required(obj, schema, &node)?;
        Ok(node)
    }

    /// The medium `obj` as a node of the scene's media (`media.ID`, its id
    /// or `medium_N` for one without), mapped once however often shapes
    /// and sensors refer to it: its name. Its phase function is the
    /// `<phase>` it holds (`isotropic` without one); a `<volume>` it holds
    /// or refers to sets the coefficient of its name (`sigma_t`, `albedo`),
    /// refused for a medium that reads none.
    pub(super) fn medium(&mut self, obj: &Object) -> Result<String, SceneError> {
        if let Some(id) = &obj.id {
            if self.media.iter().any(|m| m.id.as_ref() == Some(id)) {
                return Ok(id.clone());
            }
        }
        let name = match &obj.id {
            Some(id) => id.clone(),
            None => (1..)
                .map(|n| format!("medium_{n}"))
                .find(|n| {
                    !self.ids.map.contains_key(n)
                        && !self.media.iter().any(|m| m.id.as_ref() == Some(n))
                })
                .expect("a free name"),
        };
        let base = KeyPath::root().key("media").key(&name);
        // The plugin first: an unknown medium is refused as such.
        let schema = plugin_of((self.registry)(Kind::Medium), obj, "medium")?.schema;
        let mut phase = None;
        for c in children(self.ids, obj)? {
            match c.tag.as_str() {
                "phase" if phase.is_none() => phase = Some(c),
                "phase" => return Err(error_at(&c.at, "a second <phase> in the medium: a medium has one phase function")),
                // The volumes it reads its coefficients from: below.
                "volume" => {}
                other => {
                    return Err(error_at(
                        &c.at,
                        format!("a <{other}> inside a medium is not supported (a medium holds a phase function)"),
                    ))
                }
            }
        }
        let mut node = self.mapped(Kind::Medium, obj, base.clone())?;
        self.volume_children(obj, schema, &mut node, &base)?;
        if let Some(ph) = phase {
            node.children.push(self.phase(ph, base.key("phase"))?);
        }
        node.id = Some(name.clone());
        self.media.push(node);
        Ok(name)
    }

    /// The phase function `obj` as a node at `base`. A phase function
    /// holding others (`blendphase`) takes them from its nested `<phase>`s
    /// in order, each as the table of a phase-typed parameter (made the
    /// same way, nesting as deep as the file does), and a nested `<volume>`
    /// as its volume-typed parameter of that name; others hold nothing.
    fn phase(&mut self, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        let schema = plugin_of((self.registry)(Kind::Phase), obj, "phase")?.schema;
        let slots: Vec<&Param> = schema
            .params
            .iter()
            .filter(|p| p.ty == Type::Phase)
            .collect();
        let mut held = Vec::new();
        for c in children(self.ids, obj)? {
            match c.tag.as_str() {
                "phase" if !slots.is_empty() => held.push(c),
                "volume" if schema.params.iter().any(|p| p.ty == Type::Volume) => {}
                other => {
                    return Err(error_at(
                        &c.at,
                        format!(
                            "a <{other}> inside the phase `{}` is not supported",
                            clip(&obj.plugin)
                        ),
                    ))
                }
            }
        }
        if held.len() != slots.len() {
            let at = held.get(slots.len()).map_or(&obj.at, |c| &c.at);
            return Err(error_at(
                at,
                format!(
                    "a `{}` holds {} <phase>s, not {}",
                    clip(&obj.plugin),
                    slots.len(),
                    held.len()
                ),
            ));
        }
        let mut node = self.mapped(Kind::Phase, obj, base.clone())?;
        self.volume_children(obj, schema, &mut node, &base)?;
        for (param, child) in slots.iter().zip(held) {
            let path = base.key(param.name);
            let inner = self.phase(child, path.clone())?;
            let mut table = Node::new(Kind::Phase, "", child.at.origin(path.clone()));
            set(&mut table, &path, "type", &child.plugin_at, |p, at| {
                located(Value::String(inner.plugin.clone()), p, at)
            });
            table.props.extend(inner.props);
            set(&mut node, &base, param.name, &child.at, |p, at| {
                located(Value::Table(table.props), p, at)
            });
        }
        Ok(node)
    }

    /// Sets on `node` (at `base`) every parameter of `schema` that `obj`
    /// gives under Mitsuba's name, in the schema's order.
    pub(super) fn params(
        &self,
        obj: &Object,
        schema: &Schema,
        node: &mut Node,
        base: &KeyPath,
    ) -> Result<(), SceneError> {
        for param in schema.params {
            let Some(key) = param.mitsuba_name() else {
                continue;
            };
            if let Some((value, at)) =
                self.value(obj, key, param, schema.kind, base.key(param.name))?
            {
                let origin = at.origin(base.key(param.name));
                node.props.push(Prop::new(param.name, origin, value));
            }
        }
        Ok(())
    }

    /// The property `key` of `obj` as the value of `param` (of a plugin of
    /// `kind`) at `path`, and where it is written; `None` when `obj` does
    /// not give it.
    fn value(
        &self,
        obj: &Object,
        key: &str,
        param: &Param,
        kind: Kind,
        path: KeyPath,
    ) -> Result<Option<(Located<Value>, Place)>, SceneError> {
        let at = |a: &Place| a.clone();
        Ok(match param.ty {
            Type::Colour | Type::ColourTexture => {
                // As Mitsuba's texture getters: bounded (a reflectance),
                // emissive, or unbounded (a conductor's `eta` and `k`).
                let usage = if param.range == Range::Unit || kind == Kind::Texture {
                    Use::Reflectance
                } else if kind == Kind::Emitter {
                    Use::Emission
                } else {
                    Use::Unbounded
                };
                get_color(obj, key, usage)?.map(|(c, a)| (vec3(c, path, a), at(a)))
            }
            Type::Number | Type::NumberTexture => {
                get_float(obj, key)?.map(|(x, a)| (float(x, path, a), at(a)))
            }
            // A `<float>` or a colour where a volume is expected: a
            // constant volume (Mitsuba's `constvolume` made for it), the
            // colour unbounded; a nested `<volume>` is a child's
            // (`volume_children`).
            Type::Volume => match obj.prop(key).map(|p| &p.value) {
                None => None,
                Some(PropValue::Int(_) | PropValue::Float(_)) => {
                    get_float(obj, key)?.map(|(x, a)| (float(x, path, a), at(a)))
                }
                Some(_) => {
                    get_color(obj, key, Use::Unbounded)?.map(|(c, a)| (vec3(c, path, a), at(a)))
                }
            },
            Type::Int => get_int(obj, key)?.map(|(i, a)| (located(Value::Int(i), path, a), at(a))),
            Type::Bool => {
                get_bool(obj, key)?.map(|(b, a)| (located(Value::Bool(b), path, a), at(a)))
            }
            Type::String | Type::Choice(..) | Type::Distribution => get_string(obj, key)?
                .map(|(s, a)| (located(Value::String(s.to_string()), path, a), at(a))),
            Type::Path => match get_string(obj, key)? {
                None => None,
                Some((name, a)) => {
                    let file = self
                        .reader
                        .resolve_file(&file_dir(obj, self.reader.scene_dir), name);
                    let text = self
                        .reader
                        .scene_relative(&file)
                        .to_string_lossy()
                        .into_owned();
                    Some((located(Value::String(text), path, a), at(a)))
                }
            },
            Type::NumberOrChoice(..) => match obj.prop(key) {
                Some(p) => match &p.value {
                    PropValue::String(s) => {
                        Some((located(Value::String(s.clone()), path, &p.at), p.at.clone()))
                    }
                    _ => get_float(obj, key)?.map(|(x, a)| (float(x, path, a), at(a))),
                },
                None => None,
            },
            Type::Vector => get_vector(obj, key)?.map(|(v, a)| (vec3(v, path, a), at(a))),
            Type::Matrix4 => get_transform(obj, key)?.map(|(m, a)| (matrix(&m, path, a), at(a))),
            Type::Table(keys) => {
                get_transform(obj, key)?.map(|(m, a)| (transform_table(&m, keys, path, a), at(a)))
            }
            // One number or 3 (`rawconstant`'s `value`): a float, or a
            // point or vector, as Mitsuba takes it.
            Type::Scale => match obj.prop(key).map(|p| &p.value) {
                None => None,
                // A medium's coefficient: a float, an RGB or a spectrum,
                // unbounded.
                Some(PropValue::Rgb(_) | PropValue::Spectrum(_)) if kind == Kind::Medium => {
                    get_color(obj, key, Use::Unbounded)?.map(|(c, a)| (vec3(c, path, a), at(a)))
                }
                Some(PropValue::Vector(_)) => {
                    get_vector(obj, key)?.map(|(v, a)| (vec3(v, path, a), at(a)))
                }
                Some(PropValue::Int(_) | PropValue::Float(_)) => {
                    get_float(obj, key)?.map(|(x, a)| (float(x, path, a), at(a)))
                }
                // `constvolume`'s value, a colour as Mitsuba's texture
                // getter reads it, unbounded.
                Some(_) if kind == Kind::Volume => {
                    get_color(obj, key, Use::Unbounded)?.map(|(c, a)| (vec3(c, path, a), at(a)))
                }
                Some(_) => {
                    let p = obj.prop(key).expect("given");
                    return Err(type_error(p, "a float or a 3D vector"));
                }
            },
            Type::Numbers(_) | Type::Scale2 | Type::Matrix3 | Type::Material | Type::Phase => {
                match obj.prop(key) {
                    None => None,
                    Some(p) => {
                        return Err(type_error(p, "a value Penumbra does not read from Mitsuba"))
                    }
                }
            }
        })
    }
}

/// A Mitsuba transform as a table of `keys` at `path`: a 3 × 3 `matrix`
/// (of `(u, v)`: the upper-left 2 × 2 and the translation of the 4 × 4, as
/// Mitsuba takes `to_uv`) where the table takes one, else the 4 × 4.
fn transform_table(
    m: &super::transform::Mat4,
    keys: &[Param],
    path: KeyPath,
    at: &Place,
) -> Located<Value> {
    let inner = path.key("matrix");
    let value = if keys
        .iter()
        .any(|k| k.name == "matrix" && k.ty == Type::Matrix3)
    {
        let uv = [
            [m[0][0], m[0][1], m[0][3]],
            [m[1][0], m[1][1], m[1][3]],
            [0.0, 0.0, 1.0],
        ];
        rows(&uv, inner.clone(), at)
    } else {
        matrix(m, inner.clone(), at)
    };
    let table = vec![Prop::new("matrix", at.origin(inner), value)];
    located(Value::Table(table), path, at)
}

impl Mapper for Out<'_> {
    fn held(&self, obj: &Object) -> Result<Vec<Rc<Object>>, SceneError> {
        obj.children
            .iter()
            .map(|(_, c)| match c {
                Child::Object(o) => Ok(Rc::clone(o)),
                Child::Ref { id, at } => {
                    self.ids.get(id, at)?;
                    Ok(Rc::clone(&self.ids.map[id]))
                }
            })
            .collect()
    }

    fn bsdf_as(
        &mut self,
        inner: &Object,
        outer: &Object,
        flag: &'static str,
    ) -> Result<String, SceneError> {
        let plugin = plugin_of((self.registry)(Kind::Bsdf), inner, "bsdf")?;
        self.bsdf(inner, outer, plugin.schema, Some(flag))
    }

    fn node(&mut self, kind: Kind, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        self.mapped(kind, obj, base)
    }

    fn no_children(&self, obj: &Object) -> Result<(), SceneError> {
        Out::no_children(self, obj)
    }

    fn medium(&mut self, obj: &Object) -> Result<String, SceneError> {
        Out::medium(self, obj)
    }

    fn warn(&mut self, message: String) {
        self.warnings.push(message);
    }

    fn path_sampler(&mut self, name: &'static str, at: &Place) {
        self.path_sampler = Some((name, at.clone()));
    }
}
