//! The inverse of [lowering](super::lower): a tree back into a TOML scene
//! file, whatever it was read from (a Mitsuba XML scene, say).
//!
//! The writer knows the shape of a scene file, not its plugins: every
//! property goes to the key path it carries (`objects[2].radius`,
//! `render.width`, `camera.fov`), which lowering gave it and every other
//! reader gives it the same way. Plugin names go where lowering reads them:
//!
//! | node | its plugin name |
//! |---|---|
//! | integrator | `render.integrator` |
//! | integrator held by `aov` or `moment` | `render.nested.type` (its id at `render.nested.name`) |
//! | sensor, film, sampler | not written: it must be the one lowering makes (`perspective`, `hdrfilm`, `sets`) |
//! | emitter at `render.background` | not written: it must be `constant` |
//! | shape group at `groups.NAME` | not written: its table is the group |
//! | any other node at path `P` (`materials.NAME`, `objects[i]`, `lights[i]`, a child such as `objects[i].emitter`) | `P.type` |
//!
//! A tree lowering cannot make (a sensor of another plugin, a datetime, a
//! node or property whose path another one already holds) is refused at
//! the node or value. Writing and lowering again gives a tree
//! [`same_as`](Node::same_as) the one written; [`to_toml`]'s callers
//! check that.

use super::error::{Invalid, KeyPath, KeySeg, Origin};
use super::lower::{
    BACKGROUND_EMITTER, DEFAULT_FILM, DEFAULT_SAMPLER, DEFAULT_SENSOR, GROUP_SHAPE,
    NESTED_INTEGRATOR, ROOT_KEYS,
};
use super::tree::{Kind, Node, Prop, Value};

/// The TOML text of a scene's tree.
pub fn to_toml(root: &Node) -> Result<String, Invalid> {
    let mut doc = toml::Table::new();
    for child in &root.children {
        write_node(&mut doc, child)?;
    }
    Ok(text(&doc))
}

/// The document as a scene file: its parts in the order of [`ROOT_KEYS`],
/// a table each (`[materials.NAME]` for each material, `[[objects]]` for
/// each object), `type` and `integrator` first in each, every value inline.
fn text(doc: &toml::Table) -> String {
    let mut out = String::new();
    let mut section = |header: String, table: &toml::Table| {
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(&header);
        out.push('\n');
        let first = ["type", "integrator"];
        let keys = first
            .iter()
            .filter_map(|k| table.get_key_value(*k))
            .chain(table.iter().filter(|(k, _)| !first.contains(&k.as_str())));
        for (k, v) in keys {
            out.push_str(&format!("{} = {v}\n", key(k)));
        }
    };
    for part in ROOT_KEYS {
        match doc.get(*part) {
            Some(toml::Value::Table(t)) if matches!(*part, "materials" | "media") => {
                for (name, m) in t {
                    if let toml::Value::Table(m) = m {
                        section(format!("[{part}.{}]", key(name)), m);
                    }
                }
            }
            Some(toml::Value::Table(t)) => section(format!("[{part}]"), t),
            Some(toml::Value::Array(items)) => {
                for item in items {
                    if let toml::Value::Table(t) = item {
                        section(format!("[[{part}]]"), t);
                    }
                }
            }
            _ => {}
        }
    }
    out
}

/// A key, bare when TOML allows it, else quoted.
fn key(k: &str) -> String {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        k.to_string()
    } else {
        toml::Value::String(k.to_string()).to_string()
    }
}

fn write_node(doc: &mut toml::Table, node: &Node) -> Result<(), Invalid> {
    let implied = |name: &str| -> Result<(), Invalid> {
        if node.plugin == name {
            Ok(())
        } else {
            Err(Invalid::at(
                &node.origin,
                format!(
                    "the {} `{}` has no place in a scene file, whose {} is always `{name}`",
                    node.kind.name(),
                    node.plugin,
                    node.kind.name()
                ),
            ))
        }
    };
    let background = KeyPath::root().key("render").key("background");
    let nested = KeyPath::root().key("render").key(NESTED_INTEGRATOR);
    match node.kind {
        // The integrator `aov` or `moment` holds: `render.nested`, its
        // id its `name`.
        Kind::Integrator if node.origin.path == nested => {
            insert(
                doc,
                &nested.key("type"),
                toml::Value::String(node.plugin.clone()),
                node,
            )?;
            if let Some(id) = &node.id {
                insert(
                    doc,
                    &nested.key("name"),
                    toml::Value::String(id.clone()),
                    node,
                )?;
            }
        }
        Kind::Integrator => {
            let path = KeyPath::root().key("render").key("integrator");
            insert(doc, &path, toml::Value::String(node.plugin.clone()), node)?;
        }
        Kind::Sensor => implied(DEFAULT_SENSOR)?,
        Kind::Film => implied(DEFAULT_FILM)?,
        Kind::Sampler => implied(DEFAULT_SAMPLER)?,
        Kind::Emitter if node.origin.path == background => implied(BACKGROUND_EMITTER)?,
        // A group's table is its node: `[groups.NAME]` holds its shapes.
        Kind::Shape if node.plugin == GROUP_SHAPE => {}
        _ => {
            let path = node.origin.path.key("type");
            insert(doc, &path, toml::Value::String(node.plugin.clone()), node)?;
        }
    }
    for p in &node.props {
        insert(doc, &p.key.path, value(p)?, node)?;
    }
    for child in &node.children {
        write_node(doc, child)?;
    }
    Ok(())
}

/// A property's value as TOML.
fn value(p: &Prop) -> Result<toml::Value, Invalid> {
    fn convert(v: &Value, at: &Origin) -> Result<toml::Value, Invalid> {
        Ok(match v {
            Value::Bool(b) => toml::Value::Boolean(*b),
            Value::Int(i) => toml::Value::Integer(*i),
            Value::Float(x) if x.is_finite() => toml::Value::Float(*x),
            Value::Float(x) => {
                return Err(Invalid::at(at, format!("{x} has no place in a scene file")))
            }
            Value::String(s) => toml::Value::String(s.clone()),
            Value::Array(items) => toml::Value::Array(
                items
                    .iter()
                    .map(|i| convert(&i.value, &i.origin))
                    .collect::<Result<_, _>>()?,
            ),
            Value::Table(props) => toml::Value::Table(
                props
                    .iter()
                    .map(|p| Ok((p.name.clone(), value(p)?)))
                    .collect::<Result<_, Invalid>>()?,
            ),
            Value::Datetime(_) => {
                return Err(Invalid::at(at, "no plugin reads a datetime"));
            }
        })
    }
    convert(&p.value.value, &p.value.origin)
}

/// Puts `value` at `path` in `doc`, making the tables and arrays of tables
/// on the way; a path already holding a value is refused at `node`.
fn insert(
    doc: &mut toml::Table,
    path: &KeyPath,
    value: toml::Value,
    node: &Node,
) -> Result<(), Invalid> {
    let clash = || {
        Invalid::at(
            &node.origin,
            format!("`{path}` is written twice: the tree has no scene file"),
        )
    };
    let segs = path.segments();
    let Some((KeySeg::Key(last), init)) = segs.split_last() else {
        return Err(clash());
    };
    let mut table = doc;
    let mut i = 0;
    while i < init.len() {
        let KeySeg::Key(k) = &init[i] else {
            return Err(clash());
        };
        match init.get(i + 1) {
            Some(KeySeg::Index(n)) => {
                let entry = table
                    .entry(k.clone())
                    .or_insert_with(|| toml::Value::Array(Vec::new()));
                let toml::Value::Array(items) = entry else {
                    return Err(clash());
                };
                while items.len() <= *n {
                    items.push(toml::Value::Table(toml::Table::new()));
                }
                let toml::Value::Table(t) = &mut items[*n] else {
                    return Err(clash());
                };
                table = t;
                i += 2;
            }
            _ => {
                let entry = table
                    .entry(k.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                let toml::Value::Table(t) = entry else {
                    return Err(clash());
                };
                table = t;
                i += 1;
            }
        }
    }
    if table.contains_key(last) {
        return Err(clash());
    }
    table.insert(last.clone(), value);
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::description::from_toml;

    fn round_trip(text: &str) -> (Node, Node, String) {
        let a = from_toml(text, Path::new("a.toml")).unwrap();
        let written = to_toml(&a).unwrap();
        let b =
            from_toml(&written, Path::new("b.toml")).unwrap_or_else(|e| panic!("{e}\n{written}"));
        (a, b, written)
    }

    #[test]
    fn a_scene_file_is_written_back_to_the_same_tree() {
        let (a, b, written) = round_trip(
            r#"
[render]
width = 64
spp = 4
max_depth = 3
integrator = "path"
background = [0.05, 0.05, 0.08]

[camera]
position = [0.0, 1.5, 6.0]
fov = 40

[materials.glass]
type = "dielectric"
int_ior = 1.5

[materials.zinc]
albedo = [0.1, 0.2, 0.30000000000000004]

[[objects]]
type = "sphere"
material = "glass"
center = [1, 0.7, 0.5]
radius = 0.7
transform = { matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]] }

[[objects]]
type = "quad"
origin = [0, 0, 0]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]

[objects.emitter]
radiance = [4, 4, 4]

[[lights]]
type = "point"
position = [3.0, 3.0, 3.0]
intensity = [5, 5, 5]
"#,
        );
        assert!(a.same_as(&b), "{written}");
        assert!(
            written.contains("[[objects]]\ntype = \"sphere\"\n"),
            "{written}"
        );
        assert!(
            written.starts_with("[render]\nintegrator = \"path\"\n"),
            "{written}"
        );
        let materials = written.find("[materials.glass]").unwrap();
        assert!(
            materials < written.find("[[objects]]").unwrap(),
            "{written}"
        );
    }

    #[test]
    fn a_tree_no_scene_file_makes_is_refused() {
        let mut a = from_toml("[camera]\nfov = 30\n", Path::new("a.toml")).unwrap();
        a.child_mut(Kind::Sensor).unwrap().plugin = "thinlens".into();
        let e = to_toml(&a).unwrap_err();
        assert!(e.message.contains("sensor `thinlens`"), "{}", e.message);

        let mut b = from_toml("[camera]\nfov = 30\n", Path::new("a.toml")).unwrap();
        let fov = b.child(Kind::Sensor).unwrap().props[0].clone();
        b.child_mut(Kind::Sensor).unwrap().props.push(fov);
        let e = to_toml(&b).unwrap_err();
        assert!(
            e.message.contains("`camera.fov` is written twice"),
            "{}",
            e.message
        );
    }
}
