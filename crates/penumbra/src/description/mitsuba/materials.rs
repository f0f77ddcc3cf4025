//! Mitsuba's BSDFs and textures onto Penumbra's, through their schemas
//! (see `mapping.rs`): a `<bsdf>` becomes a `[materials.NAME]` node of the
//! plugin that reads its Mitsuba name, a `<texture>` a texture's table (or
//! `[textures.ID]` in `<scene>`). A nested `<texture name="x">` (or `<ref
//! name="x">` to one) sets the texturable parameter Mitsuba calls `x`;
//! nested `<bsdf>`s (or `<ref>`s) the parameters naming materials, in the
//! schema's order; a texture holding textures (a checkerboard's colours) and
//! an emitter taking one (a spot's `texture`) read them the same way.
//! Anything else is an error at its tag.

use std::rc::Rc;

use super::mapper::{located, obj_has, set, vec3, Out};
use super::mapping::{declared, mitsuba_keys, plugin_of, required, table_props};
use super::objects::{error_at, Child, Object, Place};
use super::parse::clip;
use super::registry::{Adapt, Mapper};
use crate::description::error::{KeyPath, SceneError};
use crate::description::schema::{MitsubaKey, Param, Schema, Type};
use crate::description::tree::{Kind, Located, Node, Prop, Value};

impl Out<'_> {
    /// The Penumbra material of a bsdf (made once per name): its name.
    pub(super) fn material(&mut self, obj: &Object) -> Result<String, SceneError> {
        let plugin = plugin_of((self.registry)(Kind::Bsdf), obj, "bsdf")?;
        if let Some(Adapt::Object(adapt)) = plugin.mitsuba.adapt {
            if let Some(made) = adapt(self, obj) {
                return made;
            }
        }
        self.bsdf(obj, obj, plugin.schema, None)
    }

    /// The material of `inner` read through `schema` under the name and
    /// at the place of `outer` (the same object but where a plugin maps a
    /// Mitsuba object onto the one it holds), `flag` set true at `outer`'s
    /// type: its name.
    pub(super) fn bsdf(
        &mut self,
        inner: &Object,
        outer: &Object,
        schema: &'static Schema,
        flag: Option<&'static str>,
    ) -> Result<String, SceneError> {
        self.no_props(inner, &mitsuba_keys(schema))?;
        let name = match outer.id.as_ref() {
            Some(id) => id.clone(),
            None => self.fresh_name(),
        };
        if !self.names.insert(name.clone()) {
            return Ok(name);
        }
        let base = KeyPath::root().key("materials").key(&name);
        let mut node = Node::new(Kind::Bsdf, schema.plugin, outer.at.origin(base.clone()));
        node.plugin_origin = outer.plugin_at.origin(base.key("type"));
        node.id = Some(name.clone());
        self.params(inner, schema, &mut node, &base)?;
        self.texture_children(inner, schema, &mut node, &base)?;
        self.held_materials(inner, schema, &mut node, &base)?;
        required(inner, schema, &node)?;
        if let Some(flag) = flag {
            set(&mut node, &base, flag, &outer.plugin_at, |p, at| {
                located(Value::Bool(true), p, at)
            });
        }
        self.bsdfs.push(node);
        Ok(name)
    }

    /// The textures `obj` holds (a nested `<texture name=...>` or a `<ref
    /// name=... id=...>` to one) as the texturable parameters of `schema`
    /// Mitsuba calls by their names (or the one taking any), set on `node`
    /// at `base`; any other child but the materials a schema holds is
    /// refused.
    pub(super) fn texture_children(
        &self,
        obj: &Object,
        schema: &Schema,
        node: &mut Node,
        base: &KeyPath,
    ) -> Result<(), SceneError> {
        let texturable: Vec<&Param> = schema.params.iter().filter(|p| p.texturable()).collect();
        let any = texturable.iter().find(|p| p.mitsuba == MitsubaKey::Any);
        let holds = schema.params.iter().any(|p| p.ty == Type::Material);
        for (name, child) in &obj.children {
            let (target, at) = match child {
                Child::Object(o) => (o.as_ref(), &o.at),
                Child::Ref { id, at } => (self.ids.get(id, at)?, at),
            };
            if target.tag != "texture" {
                if holds {
                    continue;
                }
                return Err(error_at(
                    at,
                    format!(
                        "a <{}> inside the {} `{}` is not supported",
                        target.tag,
                        obj.tag,
                        clip(&obj.plugin)
                    ),
                ));
            }
            let named = texturable
                .iter()
                .find(|p| name.is_some() && p.mitsuba_name() == name.as_deref());
            let Some(param) = any.or(named) else {
                let takes = match any {
                    Some(p) => p.name.to_string(),
                    None if texturable.is_empty() => "none".to_string(),
                    None => {
                        let names: Vec<&str> =
                            texturable.iter().filter_map(|p| p.mitsuba_name()).collect();
                        names.join(", ")
                    }
                };
                return Err(error_at(
                    at,
                    format!(
                        "a texture as `{}` of the {} `{}` is not supported (textures go to: {takes})",
                        clip(name.as_deref().unwrap_or("")),
                        obj.tag,
                        clip(&obj.plugin),
                    ),
                ));
            };
            self.texture_prop(obj, (child, target, at), param, node, base)?;
        }
        Ok(())
    }

    /// Sets `param` of `node` (at `base`) to the texture `child` of `obj`
    /// (the object `target`, at `at`): a reference to a texture declared in
    /// the scene by its id, else the texture's own table; refused if `obj`
    /// or `node` has the parameter already.
    fn texture_prop(
        &self,
        obj: &Object,
        (child, target, at): (&Child, &Object, &Place),
        param: &Param,
        node: &mut Node,
        base: &KeyPath,
    ) -> Result<(), SceneError> {
        let key = param.mitsuba_name().unwrap_or(param.name);
        if obj_has(obj, key) || node.prop(param.name).is_some() {
            return Err(error_at(at, format!("`{}` is given twice", clip(key))));
        }
        let path = base.key(param.name);
        let value = match child {
            Child::Ref { id, .. } if self.texture_ids.contains(id) => {
                located(Value::String(id.clone()), path.clone(), at)
            }
            _ => self.texture_table(target, path.clone(), at)?,
        };
        node.props
            .push(Prop::new(param.name, at.origin(path), value));
        Ok(())
    }

    /// The materials a BSDF holding others takes from its nested `<bsdf>`s
    /// (or `<ref>`s), in order: the parameters of `schema` naming
    /// materials, those without a default required.
    fn held_materials(
        &mut self,
        obj: &Object,
        schema: &Schema,
        node: &mut Node,
        base: &KeyPath,
    ) -> Result<(), SceneError> {
        let slots: Vec<&Param> = schema
            .params
            .iter()
            .filter(|p| p.ty == Type::Material)
            .collect();
        if slots.is_empty() {
            return Ok(());
        }
        let held: Vec<Rc<Object>> = self
            .held(obj)?
            .into_iter()
            .filter(|c| c.tag != "texture")
            .collect();
        if let Some(other) = held.iter().find(|c| c.tag != "bsdf") {
            return Err(error_at(
                &other.at,
                format!(
                    "a <{}> inside the bsdf `{}` is not supported: it holds <bsdf>s",
                    other.tag, obj.plugin
                ),
            ));
        }
        let required = slots.iter().filter(|p| p.default == "required").count();
        if held.len() < required || held.len() > slots.len() {
            let at = held.get(slots.len()).map_or(&obj.at, |c| &c.at);
            let count = if required == slots.len() {
                format!("{required}")
            } else {
                format!("{required} or {}", slots.len())
            };
            return Err(error_at(
                at,
                format!(
                    "a `{}` holds {count} <bsdf>s, not {}",
                    obj.plugin,
                    held.len()
                ),
            ));
        }
        for (param, child) in slots.iter().zip(held) {
            let inner = self.material(&child)?;
            set(node, base, param.name, &child.at, |p, at| {
                located(Value::String(inner), p, at)
            });
        }
        Ok(())
    }

    /// A texture declared in the scene: `textures.ID`.
    pub(super) fn texture(&mut self, obj: &Object) -> Result<(), SceneError> {
        let id = match &obj.id {
            Some(id) => id.clone(),
            None => (1..)
                .map(|n| format!("texture_{n}"))
                .find(|n| !self.texture_ids.contains(n) && !self.ids.map.contains_key(n))
                .expect("a free name"),
        };
        let base = KeyPath::root().key("textures").key(&id);
        let table = self.texture_table(obj, base.clone(), &obj.at)?;
        self.texture_ids.insert(id.clone());
        self.textures
            .push(declared(Kind::Texture, id, obj, table, base));
        Ok(())
    }

    /// A `<texture>` as the table of a texture-typed parameter at `path`:
    /// its `type` and parameters through its schema.
    fn texture_table(
        &self,
        obj: &Object,
        path: KeyPath,
        at: &Place,
    ) -> Result<Located<Value>, SceneError> {
        let plugin = plugin_of((self.registry)(Kind::Texture), obj, "texture")?;
        let schema = plugin.schema;
        table_props(obj, plugin, "texture")?;
        let mut table = Node::new(Kind::Texture, "", at.origin(path.clone()));
        set(&mut table, &path, "type", &obj.plugin_at, |p, at| {
            located(Value::String(schema.plugin.to_string()), p, at)
        });
        self.params(obj, schema, &mut table, &path)?;
        self.texture_children(obj, schema, &mut table, &path)?;
        required(obj, schema, &table)?;
        Ok(located(Value::Table(table.props), path, at))
    }

    /// Mitsuba's default material of a shape, made once each: a diffuse of
    /// reflectance 0.5, or a black one for a shape that emits (`black`).
    pub(super) fn default_material(&mut self, at: &Place, black: bool) -> String {
        let slot = usize::from(black);
        if let Some(name) = &self.default_material[slot] {
            return name.clone();
        }
        let name = self.fresh_name();
        self.names.insert(name.clone());
        let base = KeyPath::root().key("materials").key(&name);
        let mut node = Node::new(Kind::Bsdf, "diffuse", at.origin(base.clone()));
        node.id = Some(name.clone());
        if black {
            set(&mut node, &base, "reflectance", at, |p, at| {
                vec3([0.0; 3], p, at)
            });
        }
        self.bsdfs.push(node);
        self.default_material[slot] = Some(name.clone());
        name
    }
}
