//! The lights of a scene (`[[lights]]` of a scene file): a point, spot or
//! directional light, an environment map or a sky is an emitter of its
//! own; a light of a shape's type (`rect`, `sphere`, `disk`, any shape of
//! `[[objects]]`) is [lowered](lower) to that shape carrying an `area`
//! emitter, visible to rays but casting no shadow (so that it never blocks
//! its own light, as the thesis's lights do not).

use super::shapes;
use crate::description::{Kind, Located, Node, Origin, Prop, Value};
use crate::emitter::area;

/// The material a light of a shape type is made of, unless it names one:
/// black, so that its surface shows its emission alone. A scene may define
/// a material of this name to give such lights another.
pub const LIGHT_MATERIAL: &str = "penumbra:light";

/// The names a light takes for a shape beside the shapes' own.
const ALIASES: [(&str, &str); 1] = [("rect", "quad")];

/// The types of shape a light may take: `rect`, then the shapes'
/// (but a group's and an instance's).
pub fn shape_types() -> impl Iterator<Item = &'static str> {
    let shapes = shapes::SCHEMAS.iter().map(|s| s.plugin);
    ALIASES
        .iter()
        .map(|(light, _)| *light)
        .chain(shapes.filter(|p| !matches!(*p, "instance" | "shapegroup")))
}

/// Lowers the lights of `root` whose type is a shape's (`rect` for
/// `quad`): each becomes that shape carrying an `area` emitter, the
/// light's keys going to the emitter where they are the `area` emitter's
/// and to the shape otherwise. The shape casts no shadow (so that a light
/// never blocks its own light, as the thesis's lights do not) and is of
/// [`LIGHT_MATERIAL`], unless the light sets `casts_shadows` or
/// `material`. Every key keeps its place, so messages point where the
/// scene wrote it.
pub fn lower(root: &mut Node) {
    let mut black = false;
    for node in &mut root.children {
        if node.kind != Kind::Emitter {
            continue;
        }
        let plugin = match ALIASES.iter().find(|(light, _)| *light == node.plugin) {
            Some((_, shape)) => *shape,
            None => node.plugin.as_str(),
        };
        if !shape_types().any(|t| t == plugin) {
            continue;
        }
        let mut shape = Node::new(Kind::Shape, plugin, node.origin.clone());
        shape.plugin_origin = node.plugin_origin.clone();
        shape.id = node.id.take();
        let mut emitter = Node::new(Kind::Emitter, area::SCHEMA.plugin, node.origin.clone());
        emitter.plugin_origin = node.plugin_origin.clone();
        for p in node.props.drain(..) {
            match area::SCHEMA.param(&p.name) {
                Some(_) => emitter.props.push(p),
                None => shape.props.push(p),
            }
        }
        let at = |key: &str| Origin::unlocated(node.origin.path.key(key));
        if shape.prop("casts_shadows").is_none() {
            let value = Located::new(Value::Bool(false), at("casts_shadows"));
            shape
                .props
                .push(Prop::new("casts_shadows", at("casts_shadows"), value));
        }
        if shape.prop("material").is_none() {
            let value = Located::new(Value::String(LIGHT_MATERIAL.into()), at("material"));
            shape
                .props
                .push(Prop::new("material", at("material"), value));
            black = true;
        }
        shape.children.push(emitter);
        *node = shape;
    }
    let defined = root
        .children_of(Kind::Bsdf)
        .any(|m| m.id.as_deref() == Some(LIGHT_MATERIAL));
    if black && !defined {
        root.children.push(black_material(&root.origin));
    }
}

/// The thesis material that reflects and transmits nothing, named
/// [`LIGHT_MATERIAL`].
fn black_material(root: &Origin) -> Node {
    let path = root.path.key("materials").key(LIGHT_MATERIAL);
    let mut m = Node::new(Kind::Bsdf, "thesis", Origin::unlocated(path.clone()));
    m.id = Some(LIGHT_MATERIAL.into());
    let zero = Value::Float(0.0);
    for (key, value) in [
        (
            "albedo",
            Value::Array(
                (0..3)
                    .map(|i| {
                        Located::new(zero.clone(), Origin::unlocated(path.key("albedo").index(i)))
                    })
                    .collect(),
            ),
        ),
        ("shininess", zero.clone()),
        ("ior", Value::Float(1.0)),
        ("glossiness", zero.clone()),
        ("translucency", zero),
    ] {
        let at = Origin::unlocated(path.key(key));
        m.props
            .push(Prop::new(key, at.clone(), Located::new(value, at)));
    }
    m
}
