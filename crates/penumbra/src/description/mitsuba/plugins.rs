//! Mitsuba's plugins onto Penumbra's: the objects of a scene into the tree
//! a TOML scene lowers to, under the same plugin names, property names and
//! key paths (`objects[2].radius`), every value at its XML tag. The scene's
//! structure (groups, instances, the background, a shape's material and
//! emitter, the sensor's place) is mapped here; every object, the
//! integrator and the sensor too, through its plugin's schema
//! (`mapping.rs`, `materials.rs`).

use std::collections::HashSet;

use super::mapper::{children, get_color, get_transform, located, matrix, render, set, vec3, Out};
use super::mapping::plugin_of;
use super::objects::{error_at, Child, Ids, Object, Place};
use super::parse::{clip, Reader};
use super::registry::Registry;
use super::spectrum::Use;
use super::transform::Mat4;
use crate::description::error::{KeyPath, SceneError};
use crate::description::tree::{Kind, Node, Prop, Value};

/// The ids that the shapes of the scene `root`, and the shapes of its
/// groups, refer to by `<ref>`.
fn shape_refs(root: &Object) -> HashSet<String> {
    let shapes = root.children.iter().filter_map(|(_, c)| match c {
        Child::Object(o) if o.tag == "shape" => Some(o.as_ref()),
        _ => None,
    });
    let mut refs = HashSet::new();
    for shape in shapes {
        for (_, c) in &shape.children {
            match c {
                Child::Ref { id, .. } => {
                    refs.insert(id.clone());
                }
                Child::Object(o) if o.tag == "shape" => {
                    refs.extend(o.children.iter().filter_map(|(_, c)| match c {
                        Child::Ref { id, .. } => Some(id.clone()),
                        Child::Object(_) => None,
                    }));
                }
                Child::Object(_) => {}
            }
        }
    }
    refs
}

/// Builds the tree of a scene object.
pub fn scene(
    root: &Object,
    ids: &Ids,
    reader: &Reader,
    registry: Registry,
    (lenient, sensor): (bool, usize),
    warnings: &mut Vec<String>,
) -> Result<Node, SceneError> {
    let mut out = Out {
        ids,
        reader,
        registry,
        lenient,
        warnings,
        integrator: None,
        sensor: None,
        sensors: (sensor, 0),
        path_sampler: None,
        background: None,
        bsdfs: Vec::new(),
        media: Vec::new(),
        textures: Vec::new(),
        volumes: Vec::new(),
        texture_ids: root
            .children
            .iter()
            .filter_map(|(_, c)| match c {
                Child::Object(o) if o.tag == "texture" => o.id.clone(),
                _ => None,
            })
            .collect(),
        shape_refs: shape_refs(root),
        names: HashSet::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        default_material: [None, None],
    };
    out.no_props(root, &[])?;
    for (_, child) in &root.children {
        let obj = match child {
            Child::Object(o) => o.as_ref(),
            Child::Ref { at, .. } => {
                return Err(error_at(
                    at,
                    "a <ref> directly in <scene> is not supported: declare the object there",
                ))
            }
        };
        match obj.tag.as_str() {
            "integrator" => out.integrator(obj)?,
            "sensor" => out.sensor(obj)?,
            "shape" => out.shape(obj)?,
            "bsdf" => {
                out.material(obj)?;
            }
            "emitter" => out.emitter(obj)?,
            "texture" => out.texture(obj)?,
            "volume" => out.volume(obj)?,
            "medium" => {
                out.medium(obj)?;
            }
            other => {
                return Err(error_at(
                    &obj.at,
                    format!(
                        "<{other}> is not supported in a scene; Penumbra reads <integrator>, <sensor>, \
                         <shape>, <bsdf>, <emitter>, <texture>, <volume> and <medium>"
                    ),
                ))
            }
        }
    }
    let root_at = &root.at;
    let mut node = Node::new(Kind::Scene, "scene", root_at.origin(KeyPath::root()));
    let mut integrator = out
        .integrator
        .take()
        .unwrap_or_else(|| Node::new(Kind::Integrator, "path", root_at.origin(render())));
    if let Some((name, at)) = out.path_sampler.take() {
        set(&mut integrator, &render(), "path_sampler", &at, |p, at| {
            located(Value::String(name.into()), p, at)
        });
    }
    let Some(sensor) = out.sensor.take() else {
        let (wanted, found) = out.sensors;
        let message = match found {
            0 => "the scene has no <sensor>; Penumbra renders through a perspective or thinlens \
                  sensor"
                .to_string(),
            1 => format!("sensor {wanted} was asked for; the scene has one, sensor 0"),
            n => format!(
                "sensor {wanted} was asked for; the scene has {n}, 0 to {}",
                n - 1
            ),
        };
        return Err(error_at(&root.at, message));
    };
    node.children.push(integrator);
    node.children.push(sensor);
    node.children.extend(out.background.take());
    out.textures.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.textures);
    out.volumes.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.volumes);
    out.bsdfs.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.bsdfs);
    out.media.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut out.media);
    // The groups (`groups.ID`, in name order) before the objects, where a
    // scene file's lowering puts them.
    let (mut groups, mut objects): (Vec<Node>, Vec<Node>) =
        out.shapes.drain(..).partition(|n| n.id.is_some());
    groups.sort_by(|a, b| a.id.cmp(&b.id));
    node.children.append(&mut groups);
    node.children.append(&mut objects);
    node.children.append(&mut out.lights);
    Ok(node)
}

impl Out<'_> {
    /// The integrator, through the plugin that reads it, its parameters
    /// under the `render` key path and its plugin at `render.integrator`.
    fn integrator(&mut self, obj: &Object) -> Result<(), SceneError> {
        if self.integrator.is_some() {
            return Err(error_at(&obj.at, "a second <integrator>: a scene has one"));
        }
        let mut node = self.mapped(Kind::Integrator, obj, render())?;
        if matches!(obj.plugin.as_str(), "aov" | "moment") {
            node.children = self.held_integrators(obj)?;
        } else {
            self.no_children(obj)?;
        }
        node.plugin_origin = obj.plugin_at.origin(render().key("integrator"));
        self.integrator = Some(node);
        Ok(())
    }

    /// The integrators `aov` or `moment` holds, at `render.nested`, each
    /// with its name as its id: its `name`, else `_arg_N` (the `N`-th
    /// unnamed child), as Mitsuba names the channels of an unnamed child.
    fn held_integrators(&mut self, obj: &Object) -> Result<Vec<Node>, SceneError> {
        let mut unnamed = 0;
        let mut held = Vec::new();
        for (name, child) in &obj.children {
            let o = match child {
                Child::Object(o) => o.as_ref(),
                Child::Ref { id, at } => self.ids.get(id, at)?,
            };
            if o.tag != "integrator" {
                return Err(error_at(
                    &o.at,
                    format!(
                        "a <{}> inside the integrator `{}` is not supported: it holds integrators",
                        o.tag, obj.plugin
                    ),
                ));
            }
            let name = name.clone().unwrap_or_else(|| {
                unnamed += 1;
                format!("_arg_{}", unnamed - 1)
            });
            let mut node = self.mapped(Kind::Integrator, o, render().key("nested"))?;
            self.no_children(o)?;
            node.id = Some(name);
            held.push(node);
        }
        Ok(held)
    }

    /// The sensor, through the plugin that reads it: the camera, holding
    /// the film and the sampler.
    /// The sensor asked for (`--sensor`, the first by default), through
    /// the plugin that reads it; the others are counted and left unread.
    fn sensor(&mut self, obj: &Object) -> Result<(), SceneError> {
        let (wanted, found) = self.sensors;
        self.sensors.1 += 1;
        if found == wanted {
            let node = self.mapped(Kind::Sensor, obj, KeyPath::root().key("camera"))?;
            self.sensor = Some(node);
        }
        Ok(())
    }

    fn emitter(&mut self, obj: &Object) -> Result<(), SceneError> {
        match obj.plugin.as_str() {
            "constant" => {
                self.no_props(obj, &["radiance"])?;
                self.no_children(obj)?;
                if self.background.is_some() {
                    return Err(error_at(
                        &obj.at,
                        "a second `constant` emitter: Penumbra has one background",
                    ));
                }
                let path = render().key("background");
                let (radiance, at) = get_color(obj, "radiance", Use::Emission)?
                    .map_or(([1.0; 3], obj.at.clone()), |(c, at)| (c, at.clone()));
                let mut node = Node::new(Kind::Emitter, "constant", at.origin(path.clone()));
                let key = at.origin(path.clone());
                node.props
                    .push(Prop::new("radiance", key, vec3(radiance, path, &at)));
                self.background = Some(node);
            }
            // Declared in the scene and referred to by shapes (as Mitsuba
            // allows): read where they refer to it.
            "area"
                if obj
                    .id
                    .as_ref()
                    .is_some_and(|id| self.shape_refs.contains(id)) => {}
            "area" => {
                return Err(error_at(
                    &obj.at,
                    "an `area` emitter lights a shape: put it inside a <shape>, or give it an \
                     id that a <shape> refers to by <ref>",
                ))
            }
            _ => {
                let schema = plugin_of((self.registry)(Kind::Emitter), obj, "emitter")?.schema;
                if !schema.params.iter().any(|p| p.texturable()) {
                    self.no_children(obj)?;
                }
                let base = KeyPath::root().key("lights").index(self.lights.len());
                let mut node = self.mapped(Kind::Emitter, obj, base.clone())?;
                self.texture_children(obj, schema, &mut node, &base)?;
                self.lights.push(node);
            }
        }
        Ok(())
    }

    fn shape(&mut self, obj: &Object) -> Result<(), SceneError> {
        // Groups are `groups.ID`, not objects.
        let objects = self.shapes.iter().filter(|n| n.id.is_none()).count();
        let base = KeyPath::root().key("objects").index(objects);
        let node = match obj.plugin.as_str() {
            "shapegroup" => self.shapegroup(obj)?,
            "instance" => self.instance(obj, base)?,
            _ => self.shape_node(obj, base)?,
        };
        self.shapes.push(node);
        Ok(())
    }

    /// A `shapegroup` as `[groups.ID]`: its shapes, each as an object of
    /// the group.
    fn shapegroup(&mut self, obj: &Object) -> Result<Node, SceneError> {
        self.no_props(obj, &[])?;
        let Some(id) = obj.id.clone() else {
            return Err(error_at(
                &obj.at,
                "a shapegroup needs an `id`, which its instances refer to",
            ));
        };
        let path = KeyPath::root().key("groups").key(&id);
        let mut node = Node::new(Kind::Shape, "shapegroup", obj.at.origin(path.clone()));
        node.plugin_origin = obj.plugin_at.origin(path.clone());
        node.id = Some(id);
        for c in children(self.ids, obj)? {
            if c.tag != "shape" {
                return Err(error_at(
                    &c.at,
                    format!("a shapegroup holds shapes, not a <{}>", c.tag),
                ));
            }
            let base = path.key("objects").index(node.children.len());
            let child = match c.plugin.as_str() {
                // Refused by the builder: groups do not nest.
                "shapegroup" | "instance" => {
                    let mut n = Node::new(Kind::Shape, c.plugin.clone(), c.at.origin(base.clone()));
                    n.plugin_origin = c.plugin_at.origin(base.key("type"));
                    n
                }
                _ => self.shape_node(c, base)?,
            };
            node.children.push(child);
        }
        Ok(node)
    }

    /// An `instance`: the shapegroup it refers to and its `to_world`.
    fn instance(&mut self, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        self.no_props(obj, &["to_world"])?;
        let mut node = Node::new(Kind::Shape, "instance", obj.at.origin(base.clone()));
        node.plugin_origin = obj.plugin_at.origin(base.key("type"));
        let mut group = None;
        for (_, c) in &obj.children {
            let (id, at) = match c {
                Child::Ref { id, at } => (id.clone(), at),
                Child::Object(o) => {
                    return Err(error_at(
                        &o.at,
                        "an instance refers to a shapegroup by <ref id=\"...\"/>: declare the \
                         group with an id in the scene",
                    ))
                }
            };
            let target = self.ids.get(&id, at)?;
            if target.tag != "shape" || target.plugin != "shapegroup" {
                return Err(error_at(
                    at,
                    format!(
                        "an instance refers to a shapegroup; `{}` is a <{}> of type `{}`",
                        clip(&id),
                        target.tag,
                        clip(&target.plugin)
                    ),
                ));
            }
            if group.is_some() {
                return Err(error_at(at, "an instance refers to one shapegroup"));
            }
            group = Some((id, at.clone()));
        }
        let Some((id, at)) = group else {
            return Err(error_at(
                &obj.at,
                "an instance needs a <ref id=\"...\"/> to its shapegroup",
            ));
        };
        set(&mut node, &base, "group", &at, |p, at| {
            located(Value::String(id), p, at)
        });
        let to_world = get_transform(obj, "to_world")?.map(|(m, at)| (m, at.clone()));
        self.placement(&mut node, &base, &to_world);
        Ok(node)
    }

    /// The node of a shape other than a group or an instance, at `base`,
    /// with its material and the area emitter it carries.
    fn shape_node(&mut self, obj: &Object, base: KeyPath) -> Result<Node, SceneError> {
        let mut node = self.mapped(Kind::Shape, obj, base.clone())?;
        let mut material = None;
        let mut emitter = None;
        let mut media: [Option<String>; 2] = [None, None];
        for (name, child) in &obj.children {
            let c = match child {
                Child::Object(o) => o.as_ref(),
                Child::Ref { id, at } => self.ids.get(id, at)?,
            };
            if c.tag != "medium" {
                continue;
            }
            let side =
                match name.as_deref() {
                    Some("interior") => 0,
                    Some("exterior") => 1,
                    _ => return Err(error_at(
                        &c.at,
                        "a shape's medium is named `interior` or `exterior` (name=\"interior\")",
                    )),
                };
            if media[side].is_some() {
                return Err(error_at(
                    &c.at,
                    format!(
                        "a second {} medium in the shape",
                        ["interior", "exterior"][side]
                    ),
                ));
            }
            media[side] = Some(self.medium(c)?);
        }
        for (key, medium) in ["interior", "exterior"].into_iter().zip(media) {
            if let Some(m) = medium {
                set(&mut node, &base, key, &obj.at, |p, at| {
                    located(Value::String(m), p, at)
                });
            }
        }
        for c in children(self.ids, obj)? {
            match c.tag.as_str() {
                "medium" => {}
                "bsdf" if material.is_none() => material = Some(self.material(c)?),
                "emitter" if emitter.is_none() => {
                    if c.plugin != "area" {
                        return Err(error_at(&c.plugin_at, format!("a shape carries an `area` emitter, not `{}`", clip(&c.plugin))));
                    }
                    let at = base.key("emitter");
                    let schema = plugin_of((self.registry)(Kind::Emitter), c, "emitter")?.schema;
                    let mut e = self.mapped(Kind::Emitter, c, at.clone())?;
                    self.texture_children(c, schema, &mut e, &at)?;
                    e.plugin_origin = e.origin.clone();
                    emitter = Some(e);
                }
                "bsdf" | "emitter" => {
                    return Err(error_at(&c.at, format!("a second <{}> in the shape", c.tag)))
                }
                other => {
                    return Err(error_at(&c.at, format!("a <{other}> inside a shape is not supported (a shape holds a bsdf, an area emitter and media)")))
                }
            }
        }
        let material = match (material, &emitter) {
            (Some(m), _) => m,
            (None, None) => self.default_material(&obj.at, false),
            // An emitter without a bsdf reflects nothing, as in Mitsuba.
            (None, Some(_)) => self.default_material(&obj.at, true),
        };
        set(&mut node, &base, "material", &obj.at, |p, at| {
            located(Value::String(material), p, at)
        });
        node.children.extend(emitter);
        Ok(node)
    }

    /// `to_world` as the shape's `transform = { matrix = ... }`.
    fn placement(&self, node: &mut Node, base: &KeyPath, to_world: &Option<(Mat4, Place)>) {
        let Some((m, at)) = to_world else {
            return;
        };
        let path = base.key("transform");
        let inner = path.key("matrix");
        let table = vec![Prop::new(
            "matrix",
            at.origin(inner.clone()),
            matrix(m, inner, at),
        )];
        set(node, base, "transform", at, |p, at| {
            located(Value::Table(table), p, at)
        });
    }
}
