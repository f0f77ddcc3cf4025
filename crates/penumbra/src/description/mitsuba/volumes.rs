//! Mitsuba's volumes onto Penumbra's, through their schemas: a `<volume>`
//! in `<scene>` becomes `[volumes.ID]`; a `<volume name="x">` nested in a
//! plugin (a medium's `sigma_t`), or a `<ref name="x">` to one declared in
//! the scene, sets the volume-typed parameter Mitsuba calls `x` to the
//! volume's table (or its name). A `<float>` or a colour where a volume is
//! expected is a plain value, which Penumbra reads as a constant volume (as
//! Mitsuba makes a `constvolume` of it; see `mapping.rs`).

use super::mapper::{located, set, Out};
use super::mapping::{declared, plugin_of, required, table_props};
use super::objects::{error_at, Child, Object, Place};
use super::parse::clip;
use crate::description::error::{KeyPath, SceneError};
use crate::description::schema::{Schema, Type};
use crate::description::tree::{Kind, Located, Node, Value};

impl Out<'_> {
    /// A volume declared in the scene: `volumes.ID` (an id made up when it
    /// has none).
    pub(super) fn volume(&mut self, obj: &Object) -> Result<(), SceneError> {
        let id = match &obj.id {
            Some(id) => id.clone(),
            None => (1..)
                .map(|n| format!("volume_{n}"))
                .find(|n| {
                    !self.ids.map.contains_key(n)
                        && self.volumes.iter().all(|v| v.id.as_deref() != Some(n))
                })
                .expect("a free name"),
        };
        let base = KeyPath::root().key("volumes").key(&id);
        let table = self.volume_table(obj, base.clone(), &obj.at)?;
        self.volumes
            .push(declared(Kind::Volume, id, obj, table, base));
        Ok(())
    }

    /// A `<volume>` as the table of a volume-typed parameter at `path`: its
    /// `type` and parameters through its schema.
    pub(super) fn volume_table(
        &self,
        obj: &Object,
        path: KeyPath,
        at: &Place,
    ) -> Result<Located<Value>, SceneError> {
        let plugin = plugin_of((self.registry)(Kind::Volume), obj, "volume")?;
        let schema = plugin.schema;
        table_props(obj, plugin, "volume")?;
        if let Some((_, child)) = obj.children.first() {
            let at = match child {
                Child::Object(o) => &o.at,
                Child::Ref { at, .. } => at,
            };
            return Err(error_at(
                at,
                format!("the volume `{}` holds no other object", clip(&obj.plugin)),
            ));
        }
        let mut table = Node::new(Kind::Volume, "", at.origin(path.clone()));
        set(&mut table, &path, "type", &obj.plugin_at, |p, at| {
            located(Value::String(schema.plugin.to_string()), p, at)
        });
        self.params(obj, schema, &mut table, &path)?;
        required(obj, schema, &table)?;
        Ok(located(Value::Table(table.props), path, at))
    }

    /// The volumes `obj` holds (a nested `<volume name=...>`, or a `<ref
    /// name=... id=...>` to one the scene declares) as the volume-typed
    /// parameters of `schema` Mitsuba calls by their names, set on `node`
    /// at `base`. Other children are left to the caller.
    pub(super) fn volume_children(
        &self,
        obj: &Object,
        schema: &Schema,
        node: &mut Node,
        base: &KeyPath,
    ) -> Result<(), SceneError> {
        for (name, child) in &obj.children {
            let (target, at, reference) = match child {
                Child::Object(o) => (o.as_ref(), &o.at, None),
                Child::Ref { id, at } => (self.ids.get(id, at)?, at, Some(id)),
            };
            if target.tag != "volume" {
                continue;
            }
            let param = schema
                .params
                .iter()
                .filter(|p| p.ty == Type::Volume)
                .find(|p| name.is_some() && p.mitsuba_name() == name.as_deref());
            let Some(param) = param else {
                let names: Vec<&str> = schema
                    .params
                    .iter()
                    .filter(|p| p.ty == Type::Volume)
                    .filter_map(|p| p.mitsuba_name())
                    .collect();
                return Err(error_at(
                    at,
                    format!(
                        "a <volume> named `{}` is not a volume the {} `{}` reads (it reads {})",
                        clip(name.as_deref().unwrap_or("")),
                        obj.tag,
                        clip(&obj.plugin),
                        if names.is_empty() {
                            "none".to_string()
                        } else {
                            names.join(", ")
                        }
                    ),
                ));
            };
            if node.prop(param.name).is_some() {
                return Err(error_at(
                    at,
                    format!(
                        "`{}` is given twice",
                        param.mitsuba_name().unwrap_or(param.name)
                    ),
                ));
            }
            let path = base.key(param.name);
            match reference {
                // A volume of the scene, by its name.
                Some(id) => set(node, base, param.name, at, |p, at| {
                    located(Value::String(id.clone()), p, at)
                }),
                None => {
                    let table = self.volume_table(target, path, at)?;
                    node.props.push(crate::description::tree::Prop::new(
                        param.name,
                        at.origin(base.key(param.name)),
                        table,
                    ));
                }
            }
        }
        Ok(())
    }
}
